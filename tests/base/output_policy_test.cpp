// io::OutputFile and io::checkOutputPaths (output_file.hpp), the one way every
// program writes a file: a result appears under its name only whole; a failed
// write (direct or formatted) leaves the name untouched and says which file;
// symlinks, non-regular files, an input and a second output under another
// spelling are refused before anything is written.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <unistd.h>

#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "gimbalsim/io/output_file.hpp"

namespace gimbalsim::io {
namespace {

namespace fs = std::filesystem;

/// A full disk, without root: past `bytes`, write() fails with EFBIG.
struct FileSizeLimit {
  rlimit old{};
  explicit FileSizeLimit(rlim_t bytes) {
    std::signal(SIGXFSZ, SIG_IGN);
    EXPECT_EQ(::getrlimit(RLIMIT_FSIZE, &old), 0);
    rlimit small = old;
    small.rlim_cur = bytes;
    EXPECT_EQ(::setrlimit(RLIMIT_FSIZE, &small), 0);
  }
  ~FileSizeLimit() { EXPECT_EQ(::setrlimit(RLIMIT_FSIZE, &old), 0); }
};

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

TEST_F(OutputPolicy, AFolderTheUserNamedMustExistTheDefaultOneIsMade) {
  const std::string missing = (dir_ / "missing" / "sub").string();
  EXPECT_EQ(outputFolderProblem(missing, true), "no such folder (create it first)");
  EXPECT_FALSE(fs::exists(dir_ / "missing"));
  { std::ofstream(dir_ / "file") << "x"; }
  EXPECT_EQ(outputFolderProblem((dir_ / "file").string(), true), "not a folder");
  EXPECT_EQ(outputFolderProblem(dir_.string(), true), "");
  EXPECT_EQ(outputFolderProblem(missing, false), "");
  EXPECT_TRUE(fs::is_directory(missing));
  EXPECT_EQ(outputFolderProblem((dir_ / "file" / "sub").string(), false).rfind("cannot make it: ", 0), 0u);
  // a link to a folder is refused, named or default (pass 66: log2csv --out-dir wrote through it)
  fs::create_directory_symlink(missing, dir_ / "linked");
  for (const bool named : {true, false}) {
    EXPECT_EQ(outputFolderProblem((dir_ / "linked").string(), named),
              "is a link (to " + missing + "): name the folder itself");
  }
}

TEST_F(OutputPolicy, TheRunningProgramIsAnInputOfEveryRun) {
  // (pass 84) `gimbalsim simulate --out <its own executable>` replaced the program, exit 0
  const std::string self = fs::canonical("/proc/self/exe").string();
  try {
    checkOutputPaths({self});
    FAIL() << "the program's own file was accepted as an output";
  } catch (const OutputError& e) {
    EXPECT_EQ(std::string(e.what()),
              self + ": the same file as this program (the executable running); not overwritten");
  }
}

TEST_F(OutputPolicy, TheLibrariesTheProgramRunsAreInputsOfEveryRun) {
  // (pass 105) `gimbalsim simulate --out <a loaded libyaml-cpp>` replaced it, and every later run failed to start;
  // here only checked (checkOutputPaths writes nothing), on the C library this test has loaded
  std::ifstream maps("/proc/self/maps");
  std::string libc;
  for (std::string line; libc.empty() && std::getline(maps, line);) {
    if (line.find("/libc.so") != std::string::npos) libc = line.substr(line.find('/'));
  }
  ASSERT_FALSE(libc.empty()) << "no libc among the mapped files";
  try {
    checkOutputPaths({libc});
    FAIL() << "a loaded library was accepted as an output";
  } catch (const OutputError& e) {
    EXPECT_NE(std::string(e.what()).find("a library this program runs; not overwritten"), std::string::npos)
        << e.what();
  }
}

// (pass 103, 107) the scripts' lists of the programs they run by name always missed one (realpath, rmdir, then
// replaced by a benchmark's JSON): an executable file in a folder on PATH is refused; the same file outside PATH,
// a file without an execute bit and a new name in that folder are taken
TEST_F(OutputPolicy, AnExecutableFileInAFolderOnPathIsRefused) {
  fs::create_directories(dir_ / "bin");
  for (const char* name : {"bin/prog", "bin/data", "tool"}) std::ofstream(dir_ / name) << "#!/bin/sh\n";
  fs::permissions(dir_ / "bin/prog", fs::perms::owner_all | fs::perms::group_exec | fs::perms::others_exec);
  fs::permissions(dir_ / "tool", fs::perms::owner_all);
  const std::string old_path = std::getenv("PATH") ? std::getenv("PATH") : "";
  ::setenv("PATH", ("/nowhere::" + (dir_ / "bin" / ".").string() + ":/usr/bin").c_str(), 1);
  try {
    checkOutputPaths({path("bin/prog")});
    ADD_FAILURE() << "an executable on PATH was accepted as an output";
  } catch (const OutputError& e) {
    EXPECT_EQ(std::string(e.what()), path("bin/prog") + ": an executable file in " + (dir_ / "bin" / ".").string() +
                                         ", a folder on PATH (a program anything run by name may be); not overwritten");
  }
  EXPECT_NO_THROW(checkOutputPaths({path("bin/data"), path("tool"), path("bin/new")}));
  // (pass 108) a link (or a hard link) in a PATH folder makes a file elsewhere a program run by that name
  fs::create_symlink("../tool", dir_ / "bin" / "link");
  try {
    checkOutputPaths({path("tool")});
    ADD_FAILURE() << "an executable linked from a PATH folder was accepted as an output";
  } catch (const OutputError& e) {
    EXPECT_EQ(std::string(e.what()), path("tool") + ": an executable file run as " + (dir_ / "bin" / ".").string() +
                                         "/link on PATH (a program anything run by name may be); not overwritten");
  }
  ::setenv("PATH", old_path.c_str(), 1);
  EXPECT_EQ(read(path("bin/prog")), "#!/bin/sh\n");
}

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

// A run's outputs commit together: when the second one's directory vanished
// during the run (its temporary with it), the first is not left behind either.
TEST_F(OutputPolicy, AGroupWhoseSecondMemberFailsLeavesNoName) {
  fs::create_directories(dir_ / "sub");
  const std::string csv = path("run.csv"), summary = (dir_ / "sub" / "summary.json").string();
  {
    OutputFile a(csv), b(summary);
    EXPECT_TRUE(a.write("t_s\n0\n"));
    EXPECT_TRUE(b.write("{}\n"));
    fs::remove_all(dir_ / "sub");
    CommitGroup group({&a, &b});
    EXPECT_FALSE(group.commit());
    EXPECT_NE(group.error().find(summary), std::string::npos) << group.error();
  }
  EXPECT_FALSE(fs::exists(csv));
  EXPECT_EQ(entries(), 0u);  // no temporary either
}

TEST_F(OutputPolicy, AGroupWhoseFirstMemberFailsLeavesNoName) {
  fs::create_directories(dir_ / "sub");
  const std::string csv = (dir_ / "sub" / "run.csv").string(), summary = path("summary.json");
  {
    OutputFile a(csv), b(summary);
    EXPECT_TRUE(a.write("t_s\n0\n"));
    EXPECT_TRUE(b.write("{}\n"));
    fs::remove_all(dir_ / "sub");
    CommitGroup group({&a, &b});
    EXPECT_FALSE(group.commit());
    EXPECT_NE(group.error().find(csv), std::string::npos) << group.error();
  }
  EXPECT_FALSE(fs::exists(summary));
  EXPECT_EQ(entries(), 0u);
}

TEST_F(OutputPolicy, AWholeGroupAppearsAtCommit) {
  const std::string csv = path("run.csv"), summary = path("summary.json");
  {
    OutputFile a(csv), b(summary);
    EXPECT_TRUE(a.write("t_s\n"));
    EXPECT_TRUE(b.write("{}\n"));
    CommitGroup group({&a, nullptr, &b});
    EXPECT_FALSE(fs::exists(csv));
    EXPECT_TRUE(group.commit()) << group.error();
  }
  EXPECT_EQ(read(csv), "t_s\n");
  EXPECT_EQ(read(summary), "{}\n");
  EXPECT_EQ(entries(), 2u);
}

TEST_F(OutputPolicy, AnUncommittedFileLeavesNothing) {
  {
    OutputFile f(path("cut.csv"));
    f.write("half a ro");
  }
  EXPECT_EQ(entries(), 0u);
}

TEST_F(OutputPolicy, AFailedWriteNamesTheFileAndLeavesTheNameAlone) {
  const std::string p = path("full.csv");
  bool wrote_all = true;
  std::string error;
  {
    const FileSizeLimit full(4096);
    OutputFile f(p);
    const std::string row(100, 'x');
    for (int i = 0; i < 1000 && wrote_all; ++i) wrote_all = f.write(row);
    const bool committed = f.commit();
    error = f.error();
    EXPECT_FALSE(committed);
  }
  EXPECT_FALSE(wrote_all) << "a write past the limit must report failure";
  EXPECT_EQ(error.rfind(p + ": write failed: File too large", 0), 0u) << error;
  EXPECT_FALSE(fs::exists(p));
  EXPECT_EQ(entries(), 0u);
  EXPECT_THROW(writeFileAtomically(path("dir/nope.csv"), "x"), OutputError);
}

TEST_F(OutputPolicy, AFailedFormattedWriteFailsTheCommit) {
  // Rows written with fprintf on stream() (firmware_sim's truth, log2csv):
  // the stream's error flag is what ok() and commit() see.
  const std::string p = path("rows.csv");
  {
    std::ofstream(p) << "old\n";
  }
  bool ok_after_rows = true, committed = true;
  std::string error;
  {
    const FileSizeLimit full(4096);
    OutputFile f(p);
    for (int i = 0; i < 1000; ++i) std::fprintf(f.stream(), "%d,%.17g\n", i, 0.1 * i);
    ok_after_rows = f.ok();
    committed = f.commit();
    error = f.error();
  }
  EXPECT_FALSE(ok_after_rows) << "rows past the limit must show in ok()";
  EXPECT_FALSE(committed);
  EXPECT_EQ(error.rfind(p + ": write failed", 0), 0u) << error;
  EXPECT_EQ(read(p), "old\n") << "the previous file stays";
  EXPECT_EQ(entries(), 1u) << "no temporary left";
}

TEST_F(OutputPolicy, TheConstructorRefusesAnInput) {
  const std::string scene = path("scene.yaml");
  {
    std::ofstream(scene) << "name: x\n";
  }
  try {
    OutputFile f(scene, {path("other.yaml"), scene});
    FAIL() << "wrote over an input";
  } catch (const OutputError& e) {
    EXPECT_NE(std::string(e.what()).find("scene.yaml: the same file as the input"), std::string::npos) << e.what();
  }
  fs::create_hard_link(scene, path("alias.yaml"));
  EXPECT_THROW(OutputFile(path("alias.yaml"), {scene}), OutputError);
  EXPECT_NO_THROW(OutputFile(path("out.csv"), {scene}));
  EXPECT_EQ(read(scene), "name: x\n");
  EXPECT_EQ(entries(), 2u) << "an uncommitted output leaves nothing";
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
  EXPECT_THROW(OutputFile(""), OutputError);
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
