// Ctrl-C in every long subcommand: SIGINT stops the work within a second, the exit status is
// 130, and nothing is written. The work is made long on purpose (a radiosity budget of 1e11
// rays, a million samples a pixel) where it can be, so only cancellation can end it in time.

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "test_helpers.h"

namespace lb {
namespace {

namespace fs = std::filesystem;

struct Interrupted {
  int status = -1;        // exit status, -1 if it did not exit normally
  double seconds = 1e30;  // from SIGINT to exit
};

// Runs lightbake with `args`, waits for its first progress line on stderr (so the work has
// started, whatever the machine's start-up time), sends SIGINT `delay` later, and waits for it
// to exit (killing it after 20 s).
Interrupted interrupt_after(const std::vector<std::string>& args, std::chrono::milliseconds delay) {
  const std::string binary = std::string(LIGHTBAKE_BINARY_DIR) + "/app/lightbake";
  int err[2];
  if (::pipe(err) != 0) return {};
  const pid_t child = ::fork();
  if (child == 0) {
    std::vector<char*> argv{const_cast<char*>(binary.c_str())};
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    ::freopen("/dev/null", "w", stdout);
    ::dup2(err[1], STDERR_FILENO);
    ::close(err[0]);
    ::execv(binary.c_str(), argv.data());
    ::_exit(127);
  }
  ::close(err[1]);
  std::string text;
  char c = 0;
  while (text.find(" s  ") == std::string::npos && ::read(err[0], &c, 1) == 1) text += c;
  std::this_thread::sleep_for(delay);
  ::kill(child, SIGINT);
  const auto sent = std::chrono::steady_clock::now();
  Interrupted result;
  int status = 0;
  while (::waitpid(child, &status, WNOHANG) == 0) {
    if (std::chrono::steady_clock::now() - sent > std::chrono::seconds(20)) {
      ::kill(child, SIGKILL);
      ::waitpid(child, &status, 0);
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  ::close(err[0]);
  if (!WIFEXITED(status)) return result;
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - sent).count();
  result.status = WEXITSTATUS(status);
  return result;
}

fs::path fresh_dir(const std::string& name) {
  return test::fresh_dir("cli_cancel", name);
}

const std::string kRoom = test::source_dir() + "/scenes/room.toml";

// Each case: the run is still working when SIGINT comes (it would take minutes or hours).
// 1 s is the requirement; the bound of 3 s leaves room for a loaded machine, and the measured
// time goes to the test's properties.
void expect_prompt_cancel(const Interrupted& run, const fs::path& output, const char* name) {
  EXPECT_EQ(run.status, 130) << name;
  EXPECT_LT(run.seconds, 3.0) << name;
  EXPECT_FALSE(fs::exists(output)) << name << ": nothing written";
  EXPECT_EQ(fs::directory_iterator(output.parent_path()) == fs::directory_iterator(), true)
      << name << ": no temporary left";
  ::testing::Test::RecordProperty(std::string(name) + "_seconds", std::to_string(run.seconds));
}

TEST(CliCancel, BakeStopsInsideAHugeRadiosityShot) {
  const fs::path out = fresh_dir("bake") / "bake";
  const Interrupted run =
      interrupt_after({"bake", kRoom, "-o", out.string(), "--ray-budget", "100000000000"},
                      std::chrono::milliseconds(1000));
  expect_prompt_cancel(run, out, "bake");
}

// A fresh folder holding a small bake of the room in `bake`.
fs::path dir_with_bake(const std::string& name) {
  const fs::path dir = fresh_dir(name);
  const int status =
      test::run_lightbake("bake -q '" + kRoom + "' -o bake --ray-budget 20000", dir.string())
          .status;
  EXPECT_EQ(status, 0);
  return dir;
}

TEST(CliCancel, RenderStopsInsideATile) {
  const fs::path dir = dir_with_bake("render");
  const fs::path out = dir / "out" / "render.exr";
  const Interrupted run = interrupt_after({"render", kRoom, (dir / "bake").string(), "--size",
                                           "32x32", "--spp", "1000000", "-o", out.string()},
                                          std::chrono::milliseconds(500));
  expect_prompt_cancel(run, out, "render");
}

TEST(CliCancel, RenderWithFinalGatherStopsInsideAWave) {
  // 4096 gather rays per viewing path: a wave of 4096 such paths would take seconds, so waves
  // shrink with the gather (hq_render.h) and the cancel still comes within a wave.
  const fs::path dir = dir_with_bake("render_gather");
  const fs::path out = dir / "out" / "render.exr";
  const Interrupted run =
      interrupt_after({"render", kRoom, (dir / "bake").string(), "--size", "32x32", "--spp",
                       "1000000", "--final-gather=4096", "-o", out.string()},
                      std::chrono::milliseconds(500));
  expect_prompt_cancel(run, out, "render_gather");
}

TEST(CliCancel, SnapshotStopsItsBake) {
  const fs::path out = fresh_dir("snapshot") / "out" / "snapshot.png";
  fs::create_directories(out.parent_path());
  // The snapshot's own bake uses the default settings (~0.3 s here): interrupt as it starts.
  const Interrupted run =
      interrupt_after({"snapshot", kRoom, "-o", out.string()}, std::chrono::milliseconds(0));
  expect_prompt_cancel(run, out, "snapshot");
}

TEST(CliCancel, ExportStopsItsBake) {
  const fs::path out = fresh_dir("export") / "out" / "room.glb";
  fs::create_directories(out.parent_path());
  // Like snapshot, export bakes with the default settings when given no bake directory.
  const Interrupted run =
      interrupt_after({"export", kRoom, "-o", out.string()}, std::chrono::milliseconds(0));
  expect_prompt_cancel(run, out, "export");
}

TEST(CliCancel, ReferenceStopsInsideAPass) {
  const fs::path out = fresh_dir("reference") / "out" / "reference.exr";
  fs::create_directories(out.parent_path());
  const Interrupted run = interrupt_after(
      {"reference", kRoom, "--spp", "1000000", "--size", "64x48", "-o", out.string()},
      std::chrono::milliseconds(500));
  expect_prompt_cancel(run, out, "reference");
  EXPECT_FALSE(fs::exists(out.parent_path() / "reference.json")) << "no report either";
}

}  // namespace
}  // namespace lb
