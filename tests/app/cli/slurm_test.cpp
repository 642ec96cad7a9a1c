// A chunked render on a single-node Slurm (Debian 12's slurmctld and slurmd 22.05) started here as
// root in a scratch folder on chosen loopback ports, with auth/none (a test plugin: no munge, no
// systemd): a 4-task job array renders the chunks, a job that depends on it (afterok) joins them,
// and the join is the straight render. The daemons are stopped by the PIDs started. ctest -L slurm;
// .ci/run installs Slurm (SIMREEL_SLURM=1 .ci/setup) and sets SIMREEL_REQUIRE_SLURM=1, under which
// a machine that cannot run it fails instead of skipping.
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <thread>

#include "tests/cli_run.hpp"
#include "tests/scratch.hpp"

namespace simreel {
namespace {

namespace fs = std::filesystem;

test::Result sh(const std::string& cmd) {
  return test::shell(cmd);
}

std::string trim(std::string s) {
  while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
  return s;
}

// Skips, or fails where the CI asked for the test to run.
#define SKIP_OR_FAIL(msg)                                      \
  do {                                                         \
    if (std::getenv("SIMREEL_REQUIRE_SLURM")) FAIL() << (msg); \
    GTEST_SKIP() << (msg);                                     \
  } while (0)

// The daemons, stopped by PID however the test ends.
struct Daemons {
  std::string su;  // "sudo -n " when not root
  std::vector<std::string> pids;
  ~Daemons() {
    for (const std::string& p : pids) sh(su + "kill " + p);
    // slurmctld saves its state on the way out (1-2 s): wait for each to go.
    for (const std::string& p : pids)
      for (int i = 0; i < 50 && sh(su + "kill -0 " + p).code == 0; ++i)
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
};

TEST(Slurm, JobArrayRendersChunksAndTheDependentJobJoinsThem) {
  for (const char* tool : {"slurmctld", "slurmd", "sbatch", "sinfo"})
    if (sh(std::string("command -v ") + tool).code != 0)
      SKIP_OR_FAIL(std::string("no ") + tool +
                   " here (Debian: slurmctld slurmd slurm-client; SIMREEL_SLURM=1 .ci/setup)");
  // The daemons run as root: directly, or through sudo where it needs no password (as .ci/setup's apt).
  const std::string su = geteuid() == 0 ? "" : "sudo -n ";
  if (!su.empty() && sh("sudo -n true").code != 0)
    SKIP_OR_FAIL("the single-node Slurm of this test runs as root (or through sudo without a password)");
  const std::string d = test::scratch("");
  const int base = 21000 + (getpid() % 2000) * 2;
  // slurmd's spool holds Unix sockets, whose paths are at most 108 bytes: a short folder of its own.
  char spool_tmpl[] = "/tmp/slurm-XXXXXX";
  ASSERT_NE(mkdtemp(spool_tmpl), nullptr);
  const std::string spool = spool_tmpl;
  struct RemoveSpool {
    std::string dir;
    ~RemoveSpool() { sh("rm -rf " + dir); }
  } remove_spool{spool};
  fs::create_directories(d + "state");
  std::ofstream(d + "slurm.conf")
      << "ClusterName=simreeltest\nSlurmctldHost=localhost(127.0.0.1)\nSlurmctldPort=" << base
      << "\nSlurmdPort=" << base + 1 << "\nAuthType=auth/none\nCredType=cred/none\n"
      << "SlurmUser=root\nSlurmdUser=root\nStateSaveLocation=" << d << "state\nSlurmdSpoolDir=" << spool
      << "\nSlurmctldPidFile=" << d << "slurmctld.pid\nSlurmdPidFile=" << d
      << "slurmd.pid\nSlurmctldLogFile=" << d << "slurmctld.log\nSlurmdLogFile=" << d << "slurmd.log\n"
      << "ProctrackType=proctrack/linuxproc\nTaskPlugin=task/none\n"
      << "SelectType=select/cons_tres\nSelectTypeParameters=CR_Core\nMpiDefault=none\n"
      << "ReturnToService=2\nJobCompType=jobcomp/none\n"
      << "AccountingStorageType=accounting_storage/none\n"
      << "NodeName=localhost NodeAddr=127.0.0.1 CPUs=2 State=UNKNOWN\n"
      << "PartitionName=main Nodes=localhost Default=YES MaxTime=INFINITE State=UP\n";
  const std::string env = "SLURM_CONF=" + d + "slurm.conf ";
  Daemons daemons;
  daemons.su = su;
  daemons.pids.push_back(
      trim(sh(su + env + "setsid slurmctld -D -i > " + d + "ctld.out 2>&1 & echo $!").out));
  daemons.pids.push_back(
      trim(sh(su + env + "setsid slurmd -D -N localhost > " + d + "d.out 2>&1 & echo $!").out));
  std::string state;
  for (int i = 0; i < 150 && state != "idle"; ++i) {
    state = trim(sh(env + "sinfo -h -o %t").out);
    if (state != "idle") std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
  if (state != "idle")
    SKIP_OR_FAIL("the single-node Slurm did not come up (sinfo: '" + state +
                 "'): " + test::slurp(d + "slurmctld.log") + test::slurp(d + "slurmd.log"));

  // 6.5 s at 10 fps: 66 frames, 4 keyframe intervals.
  const std::string scene = "tests/data/chunks/boxes.yaml", bin = SIMREEL_BIN;
  const std::string opts = " --duration 6.5 --crf 0 --quiet";
  std::ofstream(d + "chunk.sh") << "#!/bin/sh\nexec " << bin << " render " << scene
                                << " --chunk ${SLURM_ARRAY_TASK_ID}/4 -o " << d << "parts/" << opts << "\n";
  const std::string cwd = fs::current_path().string();
  const auto array = sh(env + "sbatch --parsable --chdir=" + cwd + " --array=0-3 --output=" + d +
                        "chunk-%a.log " + d + "chunk.sh");
  ASSERT_EQ(array.code, 0) << array.out;
  const std::string job = trim(array.out);
  const auto join =
      // --wait returns when the join has run; a job Slurm cannot launch stays queued: a timeout.
      sh(env + "timeout 240 sbatch --parsable --wait --chdir=" + cwd + " --dependency=afterok:" + job +
         " --output=" + d + "join.log --wrap '" + bin + " join " + d + "parts -o " + d + "joined.mp4'");
  ASSERT_EQ(join.code, 0) << join.out << test::slurp(d + "join.log") << test::slurp(d + "chunk-0.log")
                          << sh(env + "squeue").out << test::slurp(d + "slurmd.log");
  EXPECT_NE(test::slurp(d + "join.log").find("joined 4 chunks of boxes, 66 frames"), std::string::npos)
      << test::slurp(d + "join.log");
  ASSERT_EQ(test::run("render " + scene + " -o " + d + "straight.mp4" + opts).code, 0);
  const auto diff = test::run("diff " + d + "joined.mp4 " + d + "straight.mp4 --tolerance exact --quiet");
  EXPECT_EQ(diff.code, 0) << diff.out;
}

}  // namespace
}  // namespace simreel
