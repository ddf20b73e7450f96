#include "bounded_yaml.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <yaml-cpp/eventhandler.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <sstream>
#include <vector>

#include "gimbalsim/input/input_bounds.hpp"
#include "gimbalsim/input/value_format.hpp"

namespace gimbalsim {

namespace {

/// Walks the parser's events (no tree, no alias expansion) and throws
/// PrescanRefusal at the first thing InputBounds refuses. yaml-cpp's parser
/// recurses per nesting level; refusing at kMaxDepth bounds its stack too.
class Prescan : public YAML::EventHandler {
 public:
  void OnDocumentStart(const YAML::Mark& mk) override {
    if (++documents_ > 1) refuse(mk, "more than one YAML document ('---'); give one");
  }
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark& mk, YAML::anchor_t a) override { node(mk, a, false, ""); }
  void OnAlias(const YAML::Mark& mk, YAML::anchor_t) override {
    refuse(mk, "aliases (*name) are not accepted: write the value out");
  }
  void OnScalar(const YAML::Mark& mk, const std::string&, YAML::anchor_t a, const std::string& v) override {
    if (v.size() > InputBounds::kMaxScalarBytes) {
      refuse(mk, "a value of " + std::to_string(v.size()) + " bytes (at most " +
                     std::to_string(InputBounds::kMaxScalarBytes) + ")");
    }
    node(mk, a, true, v);
  }
  void OnSequenceStart(const YAML::Mark& mk, const std::string&, YAML::anchor_t a, YAML::EmitterStyle::value) override {
    open(mk, a, false);
  }
  void OnSequenceEnd() override { frames_.pop_back(); }
  void OnMapStart(const YAML::Mark& mk, const std::string&, YAML::anchor_t a, YAML::EmitterStyle::value) override {
    open(mk, a, true);
  }
  void OnMapEnd() override { frames_.pop_back(); }
  void OnAnchor(const YAML::Mark& mk, const std::string&) override {
    refuse(mk, "anchors (&name) are not accepted: write the value out");
  }

 private:
  struct Frame {
    bool map;
    long long entries = 0;  ///< nodes seen inside; in a mapping, even = key
    std::string key;        ///< the mapping's current key
  };
  [[noreturn]] void refuse(const YAML::Mark& mk, const std::string& msg) const {
    std::string path;
    for (const Frame& f : frames_) {
      if (f.map && !f.key.empty()) path += (path.empty() ? "" : ".") + f.key;
    }
    throw PrescanRefusal{mk, path, msg};
  }
  /// Every node: counted, anchors refused, mapping keys must be non-empty scalars.
  void node(const YAML::Mark& mk, YAML::anchor_t anchor, bool scalar, const std::string& value) {
    if (anchor != YAML::NullAnchor) refuse(mk, "anchors (&name) are not accepted: write the value out");
    if (++nodes_ > InputBounds::kMaxNodes) {
      refuse(mk, "more than " + std::to_string(InputBounds::kMaxNodes) + " keys, values and list items");
    }
    if (frames_.empty()) return;
    Frame& f = frames_.back();
    if (f.map && f.entries % 2 == 0) {
      if (!scalar) refuse(mk, "a mapping key must be a plain name, not a list or mapping");
      if (value.empty()) refuse(mk, "a mapping key must not be empty");
      f.key = value;
    }
    ++f.entries;
  }
  void open(const YAML::Mark& mk, YAML::anchor_t anchor, bool map) {
    node(mk, anchor, false, "");
    if (static_cast<int>(frames_.size()) >= InputBounds::kMaxDepth) {
      refuse(mk, "nested deeper than " + std::to_string(InputBounds::kMaxDepth) + " levels");
    }
    frames_.push_back({map, 0, ""});
  }
  std::vector<Frame> frames_;
  long long nodes_ = 0;
  int documents_ = 0;
};

/// The first character YAML does not take as text (YAML 1.2, 5.1: printable
/// Unicode in UTF-8, tab and line breaks), refused with its line and column.
/// Checked before yaml-cpp reads a byte: it cut a value at a NUL and passed
/// bytes that are not UTF-8 on into names Python could not decode.
void refuseUnprintable(const std::string& text) {
  const auto* s = reinterpret_cast<const unsigned char*>(text.data());
  const std::size_t n = text.size();
  int line = 0, column = 0;
  auto refuse = [&](std::size_t at, const std::string& msg) {
    YAML::Mark mk;
    mk.pos = static_cast<int>(at);
    mk.line = line;
    mk.column = column;
    throw PrescanRefusal{mk, "", msg};
  };
  auto hex = [](unsigned v, int digits) {
    static const char* d = "0123456789abcdef";
    std::string h;
    for (int k = digits - 1; k >= 0; --k) h += d[(v >> (4 * k)) & 0xF];
    return h;
  };
  for (std::size_t i = 0; i < n;) {
    unsigned cp = 0;
    const std::size_t len = utf8At(text, i, &cp);  // 0: not UTF-8 (a shorter form, a surrogate, a cut sequence)
    if (len == 0) refuse(i, "byte 0x" + hex(s[i], 2) + " is not UTF-8 text: save the file as UTF-8");
    const bool printable = cp == 0x09 || cp == 0x0A || cp == 0x0D || (cp >= 0x20 && cp <= 0x7E) || cp == 0x85 ||
                           (cp >= 0xA0 && cp <= 0xD7FF) || (cp >= 0xE000 && cp <= 0xFFFD) || cp >= 0x10000;
    char code[8];
    std::snprintf(code, sizeof code, "%04X", cp);  // U+202E, as every message names one
    if (!printable) refuse(i, "character U+" + std::string(code) + " (a control character) is not YAML text");
    // (pass 114) a carriage return without a line feed: PyYAML breaks the line there, yaml-cpp and editors may not
    if (cp == 0x0D && (i + 1 >= n || s[i + 1] != 0x0A)) {
      refuse(i, "character U+000D without a line feed after it (a lone carriage return) splits the line an editor "
                "shows for one reader and not another (refused anywhere in a file, comments too)");
    }
    // (pass 105) in a comment too: "# was<U+2028>  restitution: 0.2" shows a line the loader never reads
    if (isLayoutCodePoint(cp)) {
      refuse(i, "character U+" + std::string(code) + " splits or reorders the line an editor shows (refused "
                "anywhere in a file, comments too)");
    }
    if (cp == 0x0A) {
      ++line;
      column = 0;
    } else {
      ++column;
    }
    i += len;
  }
}

}  // namespace

YAML::Node loadBounded(const std::string& text) {
  refuseUnprintable(text);
  std::istringstream in(text);
  YAML::Parser parser(in);
  Prescan scan;
  while (parser.HandleNextDocument(scan)) {
  }
  return YAML::Load(text);
}

bool readFile(const std::string& path, std::string& text, std::string* why) {
  auto fail = [&](const std::string& w) {
    if (why) *why = w;
    return false;
  };
  // O_NONBLOCK: opening a FIFO without a writer must not wait; fstat then refuses it.
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC);
  if (fd < 0) return fail(std::strerror(errno));
  struct Closer {
    int fd;
    ~Closer() { ::close(fd); }
  } closer{fd};
  struct stat st {};
  if (::fstat(fd, &st) != 0) return fail(std::strerror(errno));
  if (!S_ISREG(st.st_mode)) {
    return fail(S_ISDIR(st.st_mode)    ? "a directory, not a regular file"
                : S_ISFIFO(st.st_mode) ? "a FIFO, not a regular file"
                : S_ISCHR(st.st_mode)  ? "a character device, not a regular file"
                                       : "not a regular file");
  }
  if (st.st_size > InputBounds::kMaxFileBytes) {
    return fail(std::to_string(st.st_size) + " bytes, larger than " + std::to_string(InputBounds::kMaxFileBytes));
  }
  // Read at most one byte past the bound: a file that grew since fstat is refused too.
  std::string buf(static_cast<std::size_t>(InputBounds::kMaxFileBytes) + 1, '\0');
  std::size_t got = 0;
  while (got < buf.size()) {
    const ssize_t n = ::read(fd, buf.data() + got, buf.size() - got);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) return fail(std::strerror(errno));
    if (n == 0) break;
    got += static_cast<std::size_t>(n);
  }
  if (got > static_cast<std::size_t>(InputBounds::kMaxFileBytes)) {
    return fail("larger than " + std::to_string(InputBounds::kMaxFileBytes) + " bytes");
  }
  buf.resize(got);
  text = std::move(buf);
  return true;
}

}  // namespace gimbalsim
