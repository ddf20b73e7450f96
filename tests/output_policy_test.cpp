// io::OutputFile and io::checkOutputPaths (output_file.hpp): a result appears
// under its name only whole; a failed write leaves the name untouched and
// says which file; symlinks, non-regular files, an input and a second output
// under another spelling are refused before anything is written.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <unistd.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "gimbalsim/io/output_file.hpp"

namespace gimbalsim::io {
namespace {

namespace fs = std::filesystem;

class OutputPolicy : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("gimbalsim_output_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const char* name) const { return (dir_ / name).string(); }
  static std::string read(const std::string& p) {
    std::ifstream f(p);
    std::stringstream ss;
    ss << f.rdbuf();
    return ss.str();
  }
  /// Files in the directory (a leftover temporary would show here).
  std::size_t entries() const { return static_cast<std::size_t>(std::distance(fs::directory_iterator(dir_), {})); }
  fs::path dir_;
};

TEST_F(OutputPolicy, TheNameAppearsOnlyAtCommit) {
  const std::string p = path("run.csv");
  {
    std::ofstream(p) << "old\n";
  }
  OutputFile f(p);
  ASSERT_TRUE(f.write("a,b\n"));
  ASSERT_TRUE(f.write("1,2\n"));
  EXPECT_EQ(read(p), "old\n") << "the previous file stays until the new one is whole";
  EXPECT_EQ(entries(), 2u);
  ASSERT_TRUE(f.commit()) << f.error();
  EXPECT_EQ(read(p), "a,b\n1,2\n");
  EXPECT_EQ(entries(), 1u) << "no temporary left";
}

TEST_F(OutputPolicy, AnUncommittedFileLeavesNothing) {
  {
    OutputFile f(path("cut.csv"));
    f.write("half a ro");
  }
  EXPECT_EQ(entries(), 0u);
}

TEST_F(OutputPolicy, AFailedWriteNamesTheFileAndLeavesTheNameAlone) {
  // A full disk, without root: the file size limit makes write() fail with EFBIG.
  const std::string p = path("full.csv");
  std::signal(SIGXFSZ, SIG_IGN);
  rlimit old{};
  ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &old), 0);
  rlimit small = old;
  small.rlim_cur = 4096;
  ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &small), 0);
  bool wrote_all = true;
  std::string error;
  {
    OutputFile f(p);
    const std::string row(100, 'x');
    for (int i = 0; i < 1000 && wrote_all; ++i) wrote_all = f.write(row);
    const bool committed = f.commit();
    error = f.error();
    EXPECT_FALSE(committed);
  }
  ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &old), 0);
  EXPECT_FALSE(wrote_all) << "a write past the limit must report failure";
  EXPECT_EQ(error.rfind(p + ": write failed: File too large", 0), 0u) << error;
  EXPECT_FALSE(fs::exists(p));
  EXPECT_EQ(entries(), 0u);
  EXPECT_THROW(writeFileAtomically(path("dir/nope.csv"), "x"), OutputError);
}

TEST_F(OutputPolicy, SymlinksAndNonRegularFilesAreRefused) {
  const std::string target = path("target.csv");
  {
    std::ofstream(target) << "keep\n";
  }
  fs::create_symlink(target, path("link.csv"));
  try {
    OutputFile f(path("link.csv"));
    FAIL() << "wrote through a symlink";
  } catch (const OutputError& e) {
    EXPECT_NE(std::string(e.what()).find("link.csv: is a symbolic link"), std::string::npos) << e.what();
  }
  EXPECT_EQ(read(target), "keep\n");
  EXPECT_THROW(OutputFile("/dev/full"), OutputError);
  EXPECT_THROW(OutputFile(dir_.string()), OutputError);
  EXPECT_THROW(checkOutputPaths({"/dev/null"}), OutputError);
}

TEST_F(OutputPolicy, AnOutputIsNotAnInputNorAnotherOutput) {
  const std::string scene = path("scene.yaml");
  {
    std::ofstream(scene) << "name: x\n";
  }
  EXPECT_NO_THROW(checkOutputPaths({path("a.csv"), path("a.json")}, {scene}));
  // Another spelling of the same new file.
  const std::string again = (dir_ / "." / "a.csv").string();
  try {
    checkOutputPaths({path("a.csv"), again});
    FAIL() << "same output twice";
  } catch (const OutputError& e) {
    EXPECT_NE(std::string(e.what()).find("the same file as another output"), std::string::npos) << e.what();
  }
  // The scene under another spelling, and through a hard link.
  EXPECT_THROW(checkOutputPaths({(dir_ / "." / "scene.yaml").string()}, {scene}), OutputError);
  fs::create_hard_link(scene, path("hard.yaml"));
  EXPECT_THROW(checkOutputPaths({path("hard.yaml")}, {scene}), OutputError);
  EXPECT_EQ(read(scene), "name: x\n");
  EXPECT_NO_THROW(checkOutputPaths({path("out.csv"), ""}, {scene}));  // no --summary
}

}  // namespace
}  // namespace gimbalsim::io
