// torque_replay, the stand-in controller that answers a lockstep firmware_sim with a recorded run's torques:
// each way a replay is not the recorded run (another scene, another rate, a stop, a rejected answer) is said and
// exits 8 (or 2 where the input is refused), never 0 or "the plant has gone". Over LCM udpm in a private
// network namespace, as hil_lockstep_test.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <fstream>
#include <string>
#include <utility>

#include "hil_util.hpp"

namespace gimbalsim::hil {
namespace {

// A run replayed onto another plant (here the ideal joint's): the torques were answered, the dynamics differed,
// and the replay said "answered statuses 0..N", exit 0 (pass 70). Each truth message is compared with its row:
// the first joint state off it stops the replay, not reproduced (8). The slew starts at 0.5 s.
TEST(TorqueReplay, OntoAnotherSceneIsNotReproduced) {
  GIMBALSIM_HIL_REQUIRE_NETNS();
  TempDir dir("replay_other_scene");
  const std::string url = udpmUrl(7758), cfg = defaultControllerConfig();
  const std::string fw = "timeout 60 " + firmwareSim() + " --duration 0.8 --profile " + cfg + " --lcm-url '" + url +
                         "' --lockstep --start-timeout 10 ";
  const std::string body =
      "timeout 60 " + pointingController() + " " + cfg + " --lcm-url '" + url + "' --duration 0.8 --idle-exit 10 >ctl.log 2>&1 &\n"
      "C=$!\n" + fw + scenePath("paper_clearance") + " --truth-csv rec.csv >rec.log 2>&1\nrf=$?; wait $C\ntimeout 60 '" +
      std::string(GIMBALSIM_TORQUE_REPLAY) + "' rec.csv --lcm-url '" + url + "' --idle-exit 10 >replay.log 2>&1 &\n"
      "R=$!\n" + fw + scenePath("paper_ideal") + " --lockstep-timeout-ms 2000 >rep.log 2>&1\nwait $R; rr=$?\n"
      "echo \"rf $rf rr $rr\"\n[ $rf -eq 0 ] && [ $rr -eq 8 ]";
  ASSERT_EQ(runInNetns(dir, body), 0) << readFile(dir / "run.log") << readFile(dir / "rec.log")
                                      << readFile(dir / "replay.log");
  EXPECT_NE(readFile(dir / "replay.log").find("where the recorded run's row has"), std::string::npos)
      << readFile(dir / "replay.log");
  EXPECT_NE(readFile(dir / "replay.log").find("the replayed plant does not follow the recorded run"),
            std::string::npos) << readFile(dir / "replay.log");
}

// A run whose joints never moved (no torque) replayed onto a plant whose journal started elsewhere: the joint
// state matched at every tick and the replay said so, exit 0 (pass 72: a clearance run onto the ideal scene).
// Every state column is compared: the journal's eccentricity differs from tick 0, not reproduced (8).
TEST(TorqueReplay, EveryStateColumnIsCompared) {
  GIMBALSIM_HIL_REQUIRE_NETNS();
  TempDir dir("replay_state_columns");
  const std::string url = udpmUrl(7761);
  {
    std::ofstream csv(dir / "zero.csv");
    csv << "seq,sim_time_s,tau1_Nm,tau2_Nm\n";
    for (int k = 0; k <= 60; ++k) csv << k << "," << k * 0.001 << ",0,0\n";
  }
  const std::string fw = "timeout 60 " + firmwareSim() + " " + scenePath("paper_clearance") +
                         " --duration 0.06 --lcm-url '" + url + "' --lockstep --start-timeout 10 --lockstep-timeout-ms 2000";
  const std::string replay = "timeout 60 '" + std::string(GIMBALSIM_TORQUE_REPLAY) + "' ";
  const std::string body = replay + "zero.csv --lcm-url '" + url + "' >rec_replay.log 2>&1 &\nR=$!\n" + fw +
                           " --set 'initial.ecc=[1e-4, 0]' --truth-csv rec.csv >rec.log 2>&1\nrf=$?; wait $R; r0=$?\n" +
                           replay + "rec.csv --lcm-url '" + url + "' --idle-exit 5 >replay.log 2>&1 &\nR=$!\n" + fw +
                           " >fw.log 2>&1\nwait $R; r=$?\necho \"rf $rf r0 $r0 r $r\"\n"
                           "[ $rf -eq 0 ] && [ $r0 -eq 0 ] && [ $r -eq 8 ]";
  ASSERT_EQ(runInNetns(dir, body), 0) << readFile(dir / "run.log") << readFile(dir / "rec.log")
                                      << readFile(dir / "replay.log");
  const Csv rec = Csv::read(dir / "rec.csv");
  ASSERT_EQ(rec.rows.size(), 61u);
  EXPECT_EQ(rec.rows.back()[rec.col("theta2_rad")], "0") << "the joints never moved";
  EXPECT_NE(readFile(dir / "replay.log").find("torque_replay: not reproduced: truth 0 (t = 0 s): ecc2_x_m 0 where the "
                                              "recorded run's row has 0.0001"),
            std::string::npos) << readFile(dir / "replay.log");
}

// (pass 109) a plant that ended before the recording did: the replay said "the plant has gone" (6) and nothing of
// the rows it had compared; it names them, and the rows whose truth never came
TEST(TorqueReplay, APlantThatEndsFirstLeavesTheRowsNotComparedNamed) {
  GIMBALSIM_HIL_REQUIRE_NETNS();
  TempDir dir("replay_plant_first");
  const std::string url = udpmUrl(7763);
  {
    std::ofstream csv(dir / "zero.csv");
    csv << "seq,sim_time_s,tau1_Nm,tau2_Nm\n";
    for (int k = 0; k <= 60; ++k) csv << k << "," << k * 0.001 << ",0,0\n";
  }
  // a truth CSV of 61 rows recorded first (zero torques), then replayed onto a plant that runs 0.03 s of it
  const std::string replay = "timeout 60 '" + std::string(GIMBALSIM_TORQUE_REPLAY) + "' ";
  const std::string fw = "timeout 60 " + firmwareSim() + " " + scenePath("paper_ideal") + " --lcm-url '" + url +
                         "' --lockstep --start-timeout 10 ";
  const std::string body = replay + "zero.csv --lcm-url '" + url + "' >rec_replay.log 2>&1 &\nR=$!\n" + fw +
                           "--duration 0.06 --truth-csv rec.csv >rec.log 2>&1\nwait $R; r0=$?\n" + replay +
                           "rec.csv --lcm-url '" + url + "' --idle-exit 1 >replay.log 2>&1 &\nR=$!\n" + fw +
                           "--duration 0.03 >fw.log 2>&1\nwait $R; r=$?\necho \"r0 $r0 r $r\"\n"
                           "[ $r0 -eq 0 ] && [ $r -eq 6 ]";
  ASSERT_EQ(runInNetns(dir, body), 0) << readFile(dir / "run.log") << readFile(dir / "replay.log");
  const std::string log = readFile(dir / "replay.log");
  EXPECT_NE(log.find("the plant has gone"), std::string::npos) << log;
  EXPECT_NE(log.find(" of the 61 rows; no truth heard for rows "), std::string::npos) << log;
  EXPECT_NE(log.find("..60: not compared"), std::string::npos) << log;
}

// A truth CSV recorded at another control rate than the plant's: status k is
// not row k's tick, so the replay stops at the first status that says so
// (it answered tick k with the torque of another time, exit 0).
TEST(TorqueReplay, StopsAtAPlantTickingAtAnotherRate) {
  GIMBALSIM_HIL_REQUIRE_NETNS();
  TempDir dir("replay_rate");
  const std::string url = udpmUrl(7753);
  for (const auto& [name, step] : {std::pair{"ms1", 0.001}, std::pair{"ms2", 0.002}}) {
    std::ofstream csv(dir / (std::string(name) + ".csv"));
    csv << "seq,sim_time_s,tau1_Nm,tau2_Nm\n";
    for (int k = 0; k <= 60; ++k) csv << k << "," << k * step << ",0,0\n";
  }
  const std::string fw = "timeout 60 " + firmwareSim() + " " + scenePath("paper_ideal") + " --duration 0.06 --lcm-url '" +
                         url + "' --lockstep --start-timeout 10 --lockstep-timeout-ms 2000";
  const std::string replay = "timeout 60 '" + std::string(GIMBALSIM_TORQUE_REPLAY) + "' ";
  const std::string body = replay + "ms1.csv --lcm-url '" + url + "' >same.log 2>&1 &\nR=$!\n" + fw +
                           " >fw1.log 2>&1\nwait $R; r1=$?\n" + replay + "ms2.csv --lcm-url '" + url +
                           "' --idle-exit 5 >other.log 2>&1 &\nR=$!\n" + fw + " >fw2.log 2>&1\nwait $R; r2=$?\n"
                           "echo \"r1 $r1 r2 $r2\"\n[ $r1 -eq 0 ] && [ $r2 -eq 2 ]";
  ASSERT_EQ(runInNetns(dir, body), 0) << readFile(dir / "run.log") << readFile(dir / "same.log")
                                      << readFile(dir / "other.log") << readFile(dir / "fw2.log");
  EXPECT_NE(readFile(dir / "other.log")
                .find("torque_replay: error: status 1 is at t = 0.001 s, row 1 of the truth CSV at 0.002 s: the plant "
                      "ticks at another control period than the recorded run"),
            std::string::npos)
      << readFile(dir / "other.log");
}

// A plant that rejects every answer (here torques beyond its sanity range: another torque.limit than the recorded
// run's) ended the run after 30 of them, and the replay waited, then said "the plant has gone", exit 6 (pass 72).
// The recorded torques acted in the recorded run: a rejected answer is "not reproduced" (8), said from the next
// status's flags, or for status 0 (which the plant re-sends until answered) from its asking again.
TEST(TorqueReplay, ARejectedAnswerIsNotReproduced) {
  GIMBALSIM_HIL_REQUIRE_NETNS();
  TempDir dir("replay_rejected");
  const std::string url = udpmUrl(7760);
  for (const auto& [name, first_big] : {std::pair{"at0", 1}, std::pair{"at5", 6}}) {
    std::ofstream csv(dir / (std::string(name) + ".csv"));
    csv << "seq,sim_time_s,tau1_Nm,tau2_Nm\n";
    for (int k = 0; k <= 60; ++k) csv << k << "," << k * 0.001 << "," << (k >= first_big ? 1e6 : 0.0) << ",0\n";
  }
  const std::string fw = "timeout 60 " + firmwareSim() + " " + scenePath("paper_ideal") + " --duration 0.06 --lcm-url '" +
                         url + "' --lockstep --start-timeout 2 --lockstep-timeout-ms 200";
  const std::string replay = "timeout 60 '" + std::string(GIMBALSIM_TORQUE_REPLAY) + "' ";
  const std::string body = replay + "at0.csv --lcm-url '" + url + "' --idle-exit 3 >at0.log 2>&1 &\nR=$!\n" + fw +
                           " >fw0.log 2>&1\nwait $R; r0=$?\n" + replay + "at5.csv --lcm-url '" + url +
                           "' --idle-exit 3 >at5.log 2>&1 &\nR=$!\n" + fw + " >fw5.log 2>&1\nwait $R; r5=$?\n"
                           "echo \"r0 $r0 r5 $r5\"\n[ $r0 -eq 8 ] && [ $r5 -eq 8 ]";
  ASSERT_EQ(runInNetns(dir, body), 0) << readFile(dir / "run.log") << readFile(dir / "at0.log")
                                      << readFile(dir / "at5.log") << readFile(dir / "fw5.log");
  const std::string at0 = readFile(dir / "at0.log"), at5 = readFile(dir / "at5.log");
  EXPECT_NE(at0.find("torque_replay: not reproduced: the plant asked again for the answer to status 0 after it was "
                     "sent (row 1's torques 1000000, 0 N m, which acted in the recorded run)"), std::string::npos) << at0;
  EXPECT_NE(at5.find("torque_replay: not reproduced: status 6 (t = 0.006 s) says the plant rejected the answer to "
                     "status 5 (row 6's torques 1000000, 0 N m)"), std::string::npos) << at5;
  for (const std::string& log : {at0, at5}) EXPECT_EQ(log.find("the plant has gone"), std::string::npos) << log;
}

// A recorded plant that stopped (frozen rows: time still, FAULT_PLANT_FAULT) replayed against a
// plant that does not: the replay said "answered statuses 0..N" and exited 0 (pass 31); it stops
// at the first status past the recorded stop without the plant's fault, "not reproduced" (8).
TEST(TorqueReplay, OfAStopThePlantDoesNotMakeIsNotReproduced) {
  GIMBALSIM_HIL_REQUIRE_NETNS();
  TempDir dir("replay_stop");
  const std::string url = udpmUrl(7754);
  {
    std::ofstream csv(dir / "stopped.csv");
    csv << "seq,sim_time_s,tau1_Nm,tau2_Nm,faults\n";
    for (int k = 0; k <= 60; ++k) csv << k << "," << (k <= 30 ? k : 30) * 0.001 << ",0,0," << (k <= 30 ? 0 : 8) << "\n";
  }
  const std::string body = "timeout 60 '" + std::string(GIMBALSIM_TORQUE_REPLAY) + "' stopped.csv --lcm-url '" + url +
                           "' --idle-exit 5 >replay.log 2>&1 &\nR=$!\ntimeout 60 " + firmwareSim() + " " +
                           scenePath("paper_ideal") + " --duration 0.06 --lcm-url '" + url +
                           "' --lockstep --start-timeout 10 --lockstep-timeout-ms 2000 >fw.log 2>&1\nwait $R; r=$?\n"
                           "echo \"r $r\"\n[ $r -eq 8 ]";
  ASSERT_EQ(runInNetns(dir, body), 0) << readFile(dir / "run.log") << readFile(dir / "replay.log");
  EXPECT_NE(readFile(dir / "replay.log")
                .find("torque_replay: not reproduced: status 31 (t = 0.031 s) has no FAULT_PLANT_FAULT, where the "
                      "recorded plant had stopped after t = 0.03 s"),
            std::string::npos)
      << readFile(dir / "replay.log");
  // (pass 32) and the other way: a run that never stopped replayed against a plant that stops (a velocity
  // limit its first ticks already exceed) said "answered statuses 0..60", exit 0
  {
    std::ofstream csv(dir / "moving.csv");
    csv << "seq,sim_time_s,tau1_Nm,tau2_Nm,faults\n";
    for (int k = 0; k <= 60; ++k) csv << k << "," << k * 0.001 << ",5,5,0\n";
  }
  const std::string body2 = "timeout 60 '" + std::string(GIMBALSIM_TORQUE_REPLAY) + "' moving.csv --lcm-url '" + url +
                            "' --idle-exit 5 >replay2.log 2>&1 &\nR=$!\ntimeout 60 " + firmwareSim() + " " +
                            scenePath("paper_ideal") + " --duration 0.06 --lcm-url '" + url +
                            "' --lockstep --start-timeout 10 --lockstep-timeout-ms 2000 --set sim.velocity_limit=1e-3 "
                            ">fw2.log 2>&1\nwait $R; r=$?\necho \"r $r\"\n[ $r -eq 8 ]";
  ASSERT_EQ(runInNetns(dir, body2), 0) << readFile(dir / "run.log") << readFile(dir / "replay2.log")
                                       << readFile(dir / "fw2.log");
  EXPECT_NE(readFile(dir / "replay2.log").find("carries FAULT_PLANT_FAULT, where the recorded plant ran on to row "),
            std::string::npos)
      << readFile(dir / "replay2.log");
}

// A plant whose step fails inside the control period (a sub-step: sim.max_substeps 2) freezes a sub-step
// after its tick, so the truth CSV's first faulted row has its time moved on (0.57604 s). Replayed against
// the same plant it stops at that very row; the replay counted the row as motion and said "not reproduced"
// (exit 8, pass 37).
TEST(TorqueReplay, OfAStopInsideAStepIsReproduced) {
  GIMBALSIM_HIL_REQUIRE_NETNS();
  TempDir dir("replay_substep_stop");
  const std::string url = udpmUrl(7757);
  const std::string fw = "timeout 60 " + firmwareSim() + " " + scenePath("paper_clearance") +
                         " --duration 0.7 --lcm-url '" + url + "' --lockstep --start-timeout 10 "
                         "--set sim.max_substeps=2 --set contact.clearance=1e-4";
  const std::string body =
      "timeout 60 " + pointingController() + " --lcm-url '" + url + "' --duration 0.7 --idle-exit 10 >ctl.log 2>&1 &\n"
      "C=$!\n" + fw + " --truth-csv rec.csv >rec.log 2>&1\nrf=$?; wait $C\ntimeout 60 '" +
      std::string(GIMBALSIM_TORQUE_REPLAY) + "' rec.csv --lcm-url '" + url + "' --idle-exit 10 >replay.log 2>&1 &\n"
      "R=$!\n" + fw + " --truth-csv rep.csv >rep.log 2>&1\nrl=$?; wait $R; rr=$?\n"
      "echo \"rf $rf rl $rl rr $rr\"\n[ $rf -eq 3 ] && [ $rl -eq 3 ] && [ $rr -eq 0 ]";
  ASSERT_EQ(runInNetns(dir, body), 0) << readFile(dir / "run.log") << readFile(dir / "rec.log")
                                      << readFile(dir / "replay.log");
  EXPECT_NE(readFile(dir / "rec.log").find("(a sub-step from it failed)"), std::string::npos) << readFile(dir / "rec.log");
  EXPECT_EQ(readFile(dir / "rec.csv"), readFile(dir / "rep.csv"));
}

// torque_replay refuses what it cannot replay, naming the file, the line and the column.
TEST(TorqueReplay, RefusesWhatItCannotReplay) {
  TempDir dir("replay_refusals");
  const std::string prog = "'" + std::string(GIMBALSIM_TORQUE_REPLAY) + "' ";
  const std::string fifo = dir / "run.fifo";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  auto write = [&](const char* name, const char* text) {
    std::ofstream(dir / name) << text;
    return dir / name;
  };
  const struct {
    std::string path, expected;
  } cases[] = {
      {dir / "none.csv", "none.csv: cannot open truth CSV: No such file or directory"},
      {scenePath("paper_clearance"), "paper_clearance.yaml:1: no seq, tau1_Nm and tau2_Nm columns"},
      // a pipe would block, a device never end: refused at once
      {fifo, "run.fifo: not a regular file"},
      {"/dev/zero", "/dev/zero: not a regular file"},
      // written every 10 ticks (--truth-every 10): row 1 is tick 10, not tick 1
      {write("every10.csv", "seq,tau1_Nm,tau2_Nm\n0,0,0\n10,1,1\n"),
       "every10.csv:3: seq 10 where tick 1 belongs: the CSV was not written every tick"},
      {write("word.csv", "seq,tau1_Nm,tau2_Nm\n0,0.5,0\n1,abc,0\n"), "word.csv:3: column tau1_Nm: not a finite number"},
      {write("short.csv", "seq,tau1_Nm,tau2_Nm\n0,0.5\n"), "short.csv:2: 2 fields, the header has 3"},
      {write("nan.csv", "seq,tau1_Nm,tau2_Nm\n0,0,nan\n"), "nan.csv:2: column tau2_Nm: not a finite number"},
      {write("one.csv", "seq,tau1_Nm,tau2_Nm\n0,0,0\n"), "one.csv: fewer than 2 rows: nothing to replay"},
      // two columns of one name: which one the plant applied is not knowable (the last one was taken)
      {write("twice.csv", "seq,tau1_Nm,tau2_Nm,tau1_Nm\n0,0,0,1\n1,0,0,1\n"), "twice.csv:1: column tau1_Nm appears twice"},
      // blanks and hex are no number the writer writes (strtod took " 5" and "0x10")
      {write("blank.csv", "seq,tau1_Nm,tau2_Nm\n0, 5,0\n1,0,0\n"), "blank.csv:2: column tau1_Nm: not a finite number"},
      {write("hex.csv", "seq,tau1_Nm,tau2_Nm\n0,0x10,0\n1,0,0\n"), "hex.csv:2: column tau1_Nm: not a finite number"},
      // (pass 121) a leading zero, which no writer writes (a hand edit), was read as 10
      {write("lead.csv", "seq,tau1_Nm,tau2_Nm\n0,0,0\n1,-010,0\n"),
       "lead.csv:3: column tau1_Nm: '-010' has a leading zero: not a number as the CSV writer writes it"},
      // a row cut short or too long is no row of the run (it was replayed as far as it went)
      {write("cut.csv", "seq,tau1_Nm,tau2_Nm,energy_J\n0,0,0,1\n1,0,0\n"), "cut.csv:3: 3 fields, the header has 4"},
      {write("seqhex.csv", "seq,tau1_Nm,tau2_Nm\n0,0,0\n0x1,0,0\n"), "seqhex.csv:3: seq '0x1' is not a tick number"},
      // (pass 37) a leading zero is no seq the writer writes: it read as "not written every tick"
      {write("seqzero.csv", "seq,tau1_Nm,tau2_Nm\n0,0,0\n01,0,0\n"), "seqzero.csv:3: seq '01' is not a tick number"},
      // 1e-400 reads as 0: a torque nobody recorded
      {write("tiny.csv", "seq,tau1_Nm,tau2_Nm\n0,0,0\n1,1e-400,0\n"),
       "tiny.csv:3: column tau1_Nm: not a finite number (it underflows a double)"},
      // a column torque_replay does not read is still the run's: a word or a NaN there is no tick the plant made
      {write("othercol.csv", "seq,tau1_Nm,tau2_Nm,energy_J\n0,0,0,1\n1,0,0,abc\n"),
       "othercol.csv:3: column energy_J: not a finite number"},
      {write("othernan.csv", "seq,tau1_Nm,tau2_Nm,energy_J\n0,0,0,nan\n1,0,0,1\n"),
       "othernan.csv:2: column energy_J: not a finite number"},
      // an editor's CRLF line ends or byte-order mark: not the file firmware_sim wrote
      {write("crlf.csv", "seq,tau1_Nm,tau2_Nm\r\n0,0,0\r\n1,0,0\r\n"), "crlf.csv:1: ends in CR (CRLF line ends)"},
      {write("bom.csv", "\xEF\xBB\xBFseq,tau1_Nm,tau2_Nm\n0,0,0\n1,0,0\n"), "bom.csv:1: starts with a byte-order mark"},
      // (pass 72) cut while written: its last line without a line end ('16' cut to '1' would be replayed)
      {write("cutend.csv", "seq,tau1_Nm,tau2_Nm\n0,0,0\n1,0,1"), "cutend.csv:3: the last line has no line end"},
      // time that stands still or runs back: an edited file, not one run's ticks
      {write("back.csv", "seq,sim_time_s,tau1_Nm,tau2_Nm\n0,0.001,0,0\n1,0.001,0,0\n"),
       "back.csv:3: sim_time_s 0.001 is not after the previous row's"},
      // (pass 52) the tick's utime grows every tick in both modes, and is whole microseconds
      {write("uback.csv", "utime_us,seq,tau1_Nm,tau2_Nm\n4000,0,0,0\n123,1,0,0\n6000,2,0,0\n"),
       "uback.csv:3: column utime_us: 123 is not after the previous row's: not one run's ticks in order"},
      {write("ustill.csv", "utime_us,seq,tau1_Nm,tau2_Nm\n4000,0,0,0\n4000,1,0,0\n"),
       "ustill.csv:3: column utime_us: 4000 is not after the previous row's"},
      {write("uhalf.csv", "utime_us,seq,tau1_Nm,tau2_Nm\n4000,0,0,0\n5000.5,1,0,0\n"),
       "uhalf.csv:3: column utime_us: 5000.5 is not a whole number of microseconds in [0, 2^53]"},
      // (pass 53) beyond int64 on the last row, where no next row finds it
      {write("uhuge.csv", "utime_us,seq,tau1_Nm,tau2_Nm\n4000,0,0,0\n1e23,1,0,0\n"),
       "uhuge.csv:3: column utime_us: 1e23 is not a whole number of microseconds in [0, 2^53]"},
      // (pass 53) any column twice, not only a torque: base_x_m twice and base_y_m gone was taken
      {write("basex.csv", "seq,tau1_Nm,tau2_Nm,base_x_m,base_x_m\n0,0,0,0,0\n1,0,0,0,0\n"),
       "basex.csv:1: column base_x_m appears twice"},
      // (pass 51) a row off its tick's time: found only when the plant reached it, blamed on the plant's rate
      {write("uneven.csv", "seq,sim_time_s,tau1_Nm,tau2_Nm\n0,0,0,0\n1,0.001,0,0\n2,0.0025,0,0\n3,0.003,0,0\n"),
       "uneven.csv:4: column sim_time_s: 0.0025 is not tick 2's time"},
      // a plant's frozen rows carry FAULT_PLANT_FAULT (8): time standing still without it is an edit
      {write("still.csv", "seq,sim_time_s,tau1_Nm,tau2_Nm,faults\n0,0,0,0,0\n1,0.001,0,0,0\n2,0.001,0,0,4\n"),
       "still.csv:4: sim_time_s 0.001 is not after the previous row's"},
      // the fault flags are a set of bits, as plot_bench reads them: 8.5 was read as 8, -8 as no fault
      {write("halfbit.csv", "seq,sim_time_s,tau1_Nm,tau2_Nm,faults\n0,0,0,0,0\n1,0.001,0,0,8.5\n"),
       "halfbit.csv:3: column faults: 8.5 is not a set of fault bits"},
      {write("negbit.csv", "seq,sim_time_s,tau1_Nm,tau2_Nm,faults\n0,0,0,0,-8\n1,0.001,0,0,0\n"),
       "negbit.csv:2: column faults: -8 is not a set of fault bits"},
      // and nothing moves on after them
      {write("resumed.csv", "seq,sim_time_s,tau1_Nm,tau2_Nm,faults\n0,0,0,0,0\n1,0.001,0,0,0\n2,0.001,0,0,8\n"
                            "3,0.002,0,0,8\n"),
       "resumed.csv:5: sim_time_s 0.002 after the plant's stop (frozen rows before it): not one run's ticks"},
      // (pass 66) the stop is latched: a flag on one row before the run's stop was taken for the stop, and
      // the faithful replay then called "not reproduced" (exit 8)
      {write("flagonce.csv", "seq,sim_time_s,tau1_Nm,tau2_Nm,faults\n0,0,0,0,0\n1,0.001,0,0,8\n2,0.002,0,0,0\n"),
       "flagonce.csv:4: column faults: 0 lacks FAULT_PLANT_FAULT (8), latched from line 3 on: not one run's ticks"},
      {write("moveson.csv", "seq,sim_time_s,tau1_Nm,tau2_Nm,faults\n0,0,0,0,0\n1,0.001,0,0,8\n2,0.002,0,0,8\n"),
       "moveson.csv:4: sim_time_s 0.002 moves on after the plant's stop (line 3): not one run's ticks in order"},
  };
  for (const auto& c : cases) {
    int st = 0;
    const std::string out = runCapture(prog + "'" + c.path + "' --lcm-url memq:// 2>&1", &st);
    EXPECT_EQ(WEXITSTATUS(st), 2) << out;
    EXPECT_NE(out.find(c.expected), std::string::npos) << out;
  }
  // No plant at all: said as no plant (it said "after status -1", a status nobody sent), exit 6.
  int st = 0;
  const std::string out = runCapture(prog + "'" + write("two.csv", "seq,tau1_Nm,tau2_Nm\n0,0,0\n1,0,0\n") +
                                         "' --lcm-url memq:// --idle-exit 0.2 2>&1", &st);
  EXPECT_EQ(WEXITSTATUS(st), 6) << out;
  EXPECT_NE(out.find("torque_replay: error: no status for 0.2 s: no plant on GIMBAL_STATUS"), std::string::npos) << out;
  EXPECT_EQ(out.find("status -1"), std::string::npos) << out;
  // A run whose plant stopped (firmware_sim exit 3) is read whole, its frozen rows said (hil_replay: the stop).
  const std::string stopped = runCapture(
      prog + "'" + write("stopped.csv", "utime_us,seq,sim_time_s,tau1_Nm,tau2_Nm,faults\n0,0,0,0,0,0\n"
                                        "1000,1,0.001,0,0,0\n2000,2,0.001,0,0,8\n3000,3,0.001,0,0,8\n") + "' --lcm-url memq:// --idle-exit 0.2 2>&1",
      &st);
  EXPECT_EQ(WEXITSTATUS(st), 6) << stopped;  // no plant here: read, not refused
  EXPECT_NE(stopped.find("the recorded plant stopped after t = 0.001 s, its last good state (its last 2 rows are its "
                         "frozen state)"),
            std::string::npos) << stopped;
}

}  // namespace
}  // namespace gimbalsim::hil
