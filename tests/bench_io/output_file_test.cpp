// bench_io::OutputFile: the target appears only whole (commit), never through
// a symbolic link, never over an input, and a failed write leaves the target
// untouched.
#include "gimbalsim/bench_io/output_file.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace gimbalsim::bench_io {
namespace {

namespace fs = std::filesystem;

struct Dir {
  fs::path p = fs::temp_directory_path() / ("gimbalsim_out_" + std::to_string(::getpid()));
  Dir() {
    fs::remove_all(p);
    fs::create_directories(p);
  }
  ~Dir() { fs::remove_all(p); }
  std::string operator/(const std::string& f) const { return (p / f).string(); }
};

std::string slurp(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(OutputFile, TargetAppearsOnlyAtCommitAndWhole) {
  Dir d;
  const std::string path = d / "out.csv";
  {
    std::ofstream(path) << "old\n";
  }
  OutputFile f;
  std::string why;
  ASSERT_TRUE(f.open(path, &why)) << why;
  ASSERT_TRUE(f.puts("a,b\n1,2\n"));
  EXPECT_EQ(slurp(path), "old\n") << "the target is untouched until commit";
  ASSERT_TRUE(f.commit(&why)) << why;
  EXPECT_EQ(slurp(path), "a,b\n1,2\n");
  int files = 0;
  for (const auto& e : fs::directory_iterator(d.p)) files += e.is_regular_file();
  EXPECT_EQ(files, 1) << "no temporary left behind";
}

TEST(OutputFile, WithoutCommitTheTargetIsUntouchedAndTheTemporaryRemoved) {
  Dir d;
  const std::string path = d / "out.csv";
  {
    OutputFile f;
    std::string why;
    ASSERT_TRUE(f.open(path, &why)) << why;
    ASSERT_TRUE(f.puts("partial"));
  }
  EXPECT_FALSE(fs::exists(path));
  EXPECT_TRUE(fs::is_empty(d.p));
}

TEST(OutputFile, RefusesSymlinkDirectoryAndInput) {
  Dir d;
  const std::string victim = d / "victim.txt", link = d / "link.csv", scene = d / "scene.yaml";
  std::ofstream(victim) << "precious\n";
  std::ofstream(scene) << "name: x\n";
  fs::create_symlink(victim, link);
  OutputFile f;
  std::string why;
  EXPECT_FALSE(f.open(link, &why));
  EXPECT_NE(why.find("is a symbolic link"), std::string::npos) << why;
  EXPECT_FALSE(f.open(d.p.string(), &why));
  EXPECT_NE(why.find("not a regular file"), std::string::npos) << why;
  EXPECT_FALSE(f.open(scene, &why, {scene}));
  EXPECT_NE(why.find("is the input"), std::string::npos) << why;
  // The same file under another name (a hard link) is still the input.
  fs::create_hard_link(scene, d / "alias.yaml");
  EXPECT_FALSE(f.open(d / "alias.yaml", &why, {scene}));
  EXPECT_EQ(slurp(victim), "precious\n");
  EXPECT_EQ(slurp(scene), "name: x\n");
}

TEST(OutputFile, AFailedWriteFailsTheCommitAndLeavesTheTargetUntouched) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  Dir d;
  const std::string path = d / "out.csv";
  std::ofstream(path) << "old\n";
  OutputFile f;
  std::string why;
  ASSERT_TRUE(f.open(path, &why)) << why;
  // Point the stream at /dev/full (ENOSPC on every write): a full disk.
  std::FILE* full = std::freopen("/dev/full", "w", f.file());
  ASSERT_NE(full, nullptr);
  std::string big(1 << 16, 'x');
  f.write(big.data(), big.size());
  EXPECT_FALSE(f.commit(&why));
  EXPECT_NE(why.find("writing failed"), std::string::npos) << why;
  EXPECT_EQ(slurp(path), "old\n");
}

}  // namespace
}  // namespace gimbalsim::bench_io
