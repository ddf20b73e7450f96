#include "errors.hpp"

#include <cstdio>
#include <sstream>

#include <unistd.h>

namespace gimbalsim::py {

namespace pyb = pybind11;

namespace {
[[noreturn]] void raise(const char* type, pyb::object instance) {
  const pyb::object cls = pyb::module_::import("gimbalsim._errors").attr(type);
  PyErr_SetObject(cls.ptr(), instance.ptr());
  throw pyb::error_already_set();
}
}  // namespace

void raiseSceneError(const InputError& e) {
  pyb::list problems;
  for (const Problem& p : e.details()) {
    pyb::dict d;
    d["text"] = p.text;
    d["key"] = p.key.empty() ? pyb::object(pyb::none()) : pyb::object(pyb::str(p.key));
    d["file"] = p.file.empty() ? pyb::object(pyb::none()) : pyb::object(pyb::str(p.file));
    d["line"] = p.line > 0 ? pyb::object(pyb::int_(p.line)) : pyb::object(pyb::none());
    d["column"] = p.column > 0 ? pyb::object(pyb::int_(p.column)) : pyb::object(pyb::none());
    d["set_index"] = p.set_index > 0 ? pyb::object(pyb::int_(p.set_index)) : pyb::object(pyb::none());
    problems.append(d);
  }
  const pyb::object cls = pyb::module_::import("gimbalsim._errors").attr("SceneError");
  raise("SceneError", cls(e.what(), problems));
}

void raiseStopped(const StepResult& r, const std::string& message, pyb::dict extra) {
  const pyb::object cls = pyb::module_::import("gimbalsim._errors").attr("SimulationStopped");
  pyb::object ex = cls(message, r.key(), describe(r.status), r.time);
  for (auto item : extra) pyb::setattr(ex, item.first, item.second);
  raise("SimulationStopped", ex);
}

void fitsInMemory(double need_bytes, const std::string& subject, const std::string& detail, const std::string& tail) {
  const double have_bytes =
      static_cast<double>(sysconf(_SC_AVPHYS_PAGES)) * static_cast<double>(sysconf(_SC_PAGE_SIZE));
  if (need_bytes <= have_bytes) return;
  char text[900];
  std::snprintf(text, sizeof text, "%s need %.3g GB (%s), more than the %.3g GB of memory free now%s", subject.c_str(),
                need_bytes / 1e9, detail.c_str(), have_bytes / 1e9, tail.c_str());
  PyErr_SetString(PyExc_MemoryError, text);
  throw pyb::error_already_set();
}

std::size_t rowsFitInMemory(double rows, int columns, const std::string& what) {
  char subject[64], detail[64];
  std::snprintf(subject, sizeof subject, ": %.0f rows", rows);
  std::snprintf(detail, sizeof detail, "%d columns a row, twice", columns);
  fitsInMemory(rows * columns * sizeof(double) * 2.0, what + subject, detail, "");
  return static_cast<std::size_t>(rows);
}

}  // namespace gimbalsim::py
