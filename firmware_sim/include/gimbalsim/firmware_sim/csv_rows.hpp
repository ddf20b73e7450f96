// CSV rows of the bench messages, one format for everyone who writes them:
// firmware_sim --truth-csv (from its Truth struct) and gimbalsim_log2csv
// (from the decoded LCM types of a log). Header and rows both come from the
// message's field list (messages.hpp), so the columns are listed once and the
// two programs write the same bytes for the same message. The field lists'
// `name[unit]` become the project's CSV names (io::csvNameOf: `name_unit`);
// numbers are io::formatCsvNumber (a row round-trips exactly), integers %lld.
#pragma once

#include <cmath>
#include <cstdio>
#include <string>
#include <type_traits>

#include "gimbalsim/contract/messages.hpp"
#include "gimbalsim/io/csv_format.hpp"

namespace gimbalsim::firmware::csv {
using namespace gimbalsim::contract;  // NOLINT(google-build-using-namespace): the message field lists

namespace detail {
template <class T>
void put(std::FILE* f, const T& x, const char* sep) {
  if constexpr (std::is_floating_point_v<T>) {
    char buf[32];
    const int n = io::formatCsvNumber(buf, static_cast<double>(x));
    std::fprintf(f, "%s%.*s", sep, n, buf);
  } else {
    static_assert(std::is_integral_v<T>);
    std::fprintf(f, "%s%lld", sep, static_cast<long long>(x));
  }
}
template <class T, std::size_t N>
void put(std::FILE* f, const T (&x)[N], const char* sep) {
  for (std::size_t i = 0; i < N; ++i) put(f, x[i], i == 0 ? sep : ",");
}
}  // namespace detail

/// The header line of message type D (TruthFields, StatusFields, ...), with
/// newline; without its first `skip` fields when appended to another's row.
template <class D>
std::string header(int skip = 0) {
  std::string h;
  int field = 0;
  D::visit([&](Columns cols) {
    if (field++ < skip) return;
    for (const char* c : cols) (h.empty() ? h : h += ',') += io::csvNameOf(c);
  });
  return h + '\n';
}

namespace detail {
/// m's fields after its first `skip`, each after `sep` (then ","), as D orders them.
template <class D, class M>
void putFields(std::FILE* f, const M& m, int skip, const char* sep) {
  int field = 0;
  D::visit(
      [&](Columns, const auto& x) {
        if (field++ < skip) return;
        put(f, x, sep);
        sep = ",";
      },
      m);
}
}  // namespace detail

/// Every number of m finite: what a bench message holds (a NaN or Inf is no CSV cell's value, and none of
/// the project's programs sends one; one on the wire came from elsewhere).
template <class D, class M>
bool allFinite(const M& m) {
  bool finite = true;
  auto check = [&finite](const auto& x) {
    if constexpr (std::is_floating_point_v<std::remove_cvref_t<decltype(x)>>) finite = finite && std::isfinite(x);
  };
  D::visit(
      [&](Columns, const auto& x) {
        if constexpr (std::is_array_v<std::remove_cvref_t<decltype(x)>>) {
          for (const auto& v : x) check(v);
        } else {
          check(x);
        }
      },
      m);
  return finite;
}

/// One row of m (a firmware struct or the LCM type) as the field list D
/// orders it; end = false leaves it open for continueRow().
template <class D, class M>
void writeRow(std::FILE* f, const M& m, bool end = true) {
  detail::putFields<D>(f, m, 0, "");
  if (end) std::fputc('\n', f);
}

/// Continues an open row with another message's fields (after a comma),
/// leaving out its first `skip` (fields the row already holds), and ends it.
template <class D, class M>
void continueRow(std::FILE* f, const M& m, int skip) {
  detail::putFields<D>(f, m, skip, ",");
  std::fputc('\n', f);
}

}  // namespace gimbalsim::firmware::csv
