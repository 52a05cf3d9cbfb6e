// Where a bake may be written: a new or empty folder, or a previous bake (replaced, the user's
// other files kept); any other folder is refused unless --force, a file always. A SIGKILL at
// any moment of a save leaves the previous bake whole and loadable, and the temporaries a
// killed save leaves behind are swept by the next one.

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <thread>

#include "bake/io/atomic_file.h"
#include "bake/pipeline/bake.h"
#include "bake/pipeline/bake_io.h"
#include "scenes.h"
#include "test_helpers.h"

namespace lb {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::Not;

fs::path fresh_dir(const std::string& name) {
  return test::fresh_dir("bake_destination", name);
}

void write_text(const fs::path& path, const std::string& text) {
  fs::create_directories(path.parent_path());
  std::ofstream(path) << text;
}

std::string read_text(const fs::path& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

std::vector<std::string> entries(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

// How many temporaries of `path` stand beside it.
int temporaries_beside(const fs::path& path) {
  const std::string prefix = "." + path.filename().string() + ".tmp-";
  int count = 0;
  for (const std::string& name : entries(path.parent_path())) count += name.starts_with(prefix);
  return count;
}

// A user's folder: what a mistyped -o must never lose.
void fill_users_folder(const fs::path& dir) {
  write_text(dir / "level.blend", "a week of work");
  write_text(dir / "notes" / "todo.txt", "relight the hall");
}

void expect_users_files(const fs::path& dir) {
  EXPECT_EQ(read_text(dir / "level.blend"), "a week of work");
  EXPECT_EQ(read_text(dir / "notes" / "todo.txt"), "relight the hall");
}

SaveBakeOptions forced() {
  SaveBakeOptions options;
  options.force = true;
  return options;
}

BakeResult small_bake(const Scene& scene, uint64_t seed = 5) {
  BakeParams params;
  params.illumination.rays_per_zone_side = 16;
  params.radiosity.ray_budget = 50'000;
  params.seed = seed;
  return bake_scene(scene, params);
}

TEST(BakeDestination, RefusesAFolderThatHoldsNoBake) {
  const Scene scene = test::make_room_with_mirror();
  const fs::path dir = fresh_dir("users_folder");
  fill_users_folder(dir);
  try {
    save_bake(dir.string(), scene, small_bake(scene));
    FAIL() << "a folder with no bake in it must be refused";
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), HasSubstr(dir.string() + ": is a folder that holds no bake"));
    EXPECT_THAT(e.what(), HasSubstr("--force"));
  }
  EXPECT_EQ(entries(dir), (std::vector<std::string>{"level.blend", "notes"}));
  expect_users_files(dir);
  EXPECT_EQ(temporaries_beside(dir), 0);
  EXPECT_THROW(check_bake_destination(dir.string(), false), std::runtime_error);
  EXPECT_NO_THROW(check_bake_destination(dir.string(), true));
  EXPECT_NO_THROW(check_bake_destination((dir / "new").string(), false));
}

TEST(BakeDestination, ForceAddsTheBakeAndKeepsEveryFile) {
  const Scene scene = test::make_room_with_mirror();
  const fs::path dir = fresh_dir("forced");
  fill_users_folder(dir);
  const BakeResult bake = small_bake(scene);
  save_bake(dir.string(), scene, bake, forced());
  expect_users_files(dir);
  EXPECT_EQ(load_bake(dir.string(), scene).seed, bake.seed);
  EXPECT_TRUE(is_bake_directory(dir.string()));
}

TEST(BakeDestination, ReplacesAPreviousBakeAndKeepsWhatTheUserAdded) {
  const Scene with_caustics = test::make_room_with_mirror();
  const fs::path dir = fresh_dir("previous") / "bake";
  save_bake(dir.string(), with_caustics, small_bake(with_caustics));
  ASSERT_TRUE(fs::exists(dir / "illumination.exr"));
  write_text(dir / "render.png", "a render the user made here");
  write_text(dir / "notes" / "todo.txt", "relight the hall");

  // A scene without specular objects: its map (every texel 0, the atlas covers every diffuse
  // mesh) replaces the old one, while the render and the notes stay.
  const Scene plain = test::make_room();
  const BakeResult bake = small_bake(plain, 9);
  ASSERT_GT(bake.illumination.width, 0);
  save_bake(dir.string(), plain, bake);
  EXPECT_EQ(entries(dir),
            (std::vector<std::string>{"illumination.bin", "illumination.exr", "manifest.json",
                                      "notes", "radiosity.bin", "render.png", "soft_light.exr"}));
  EXPECT_EQ(load_bake(dir.string(), plain).illumination.width, bake.illumination.width);
  EXPECT_EQ(read_text(dir / "render.png"), "a render the user made here");
  EXPECT_EQ(read_text(dir / "notes" / "todo.txt"), "relight the hall");
  EXPECT_EQ(load_bake(dir.string(), plain).seed, 9u);
  EXPECT_EQ(entries(dir.parent_path()), std::vector<std::string>{"bake"}) << "no temporary";
}

TEST(BakeDestination, RefusesAFileAndTheCurrentFolder) {
  const Scene scene = test::make_room();
  const fs::path dir = fresh_dir("file");
  write_text(dir / "bake", "not a folder");
  EXPECT_THROW(save_bake((dir / "bake").string(), scene, small_bake(scene), forced()),
               std::runtime_error);
  EXPECT_EQ(read_text(dir / "bake"), "not a folder");

  // Even forced, the folder a process stands in is not swapped from under it.
  save_bake((dir / "here").string(), scene, small_bake(scene));
  const fs::path before = fs::current_path();
  fs::current_path(dir / "here");
  EXPECT_THROW(AtomicDirectory("."), std::runtime_error);
  fs::current_path(before);
}

TEST(BakeDestination, CliRefusesAUsersFolderBeforeBaking) {
  const fs::path dir = fresh_dir("cli");
  fill_users_folder(dir / "project");
  const std::string scene = test::source_dir() + "/scenes/room.toml";
  for (const std::string& output : {"'" + (dir / "project").string() + "'", std::string(".")}) {
    const test::CliRun run =
        test::run_lightbake("bake -q '" + scene + "' -o " + output, (dir / "project").string());
    EXPECT_EQ(run.status, 1) << run.err;
    EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
    EXPECT_THAT(run.err, HasSubstr("is a folder that holds no bake"));
    EXPECT_THAT(run.out, Not(HasSubstr("radiosity"))) << "refused before baking";
    EXPECT_EQ(entries(dir / "project"), (std::vector<std::string>{"level.blend", "notes"}));
    expect_users_files(dir / "project");
  }
  EXPECT_EQ(entries(dir), std::vector<std::string>{"project"}) << "no temporary";
}

// The PID of a process that has exited (and been reaped).
pid_t dead_pid() {
  const pid_t child = ::fork();
  if (child == 0) ::_exit(0);
  ::waitpid(child, nullptr, 0);
  return child;
}

TEST(BakeDestination, TemporariesOfDeadProcessesAreSweptAndNothingElse) {
  const Scene scene = test::make_room();
  const fs::path dir = fresh_dir("sweep");
  save_bake((dir / "bake").string(), scene, small_bake(scene));
  const std::string dead = std::to_string(dead_pid());
  const std::string alive = std::to_string(::getpid());
  write_text(dir / (".bake.tmp-" + dead + "-0") / "manifest.json", "{}");   // a killed bake
  write_text(dir / (".bake.tmp-" + dead + "-3"), "x");                      // a killed file write
  write_text(dir / (".bake.tmp-" + alive + "-7") / "manifest.json", "{}");  // still running
  write_text(dir / (".bake.tmp-" + dead + "-1x"), "not ours");
  write_text(dir / (".other.tmp-" + dead + "-0"), "another target's");
  // A killed first bake's directory may be all there is (see sweep_stale_temporaries): kept
  // while no final folder exists, swept once one does.
  save_bake((dir / "bake").string(), scene, small_bake(scene));
  EXPECT_EQ(entries(dir),
            (std::vector<std::string>{".bake.tmp-" + alive + "-7", ".bake.tmp-" + dead + "-1x",
                                      ".other.tmp-" + dead + "-0", "bake"}));
}

// Spawns bake_save_loop, alternating the bakes in `first` and `second` into `dir`; returns its
// PID once it has saved one whole bake.
pid_t start_save_loop(const fs::path& first, const fs::path& second, const fs::path& dir) {
  int pipe_fds[2];
  if (::pipe(pipe_fds) != 0) return -1;
  const pid_t child = ::fork();
  if (child == 0) {
    ::dup2(pipe_fds[1], STDOUT_FILENO);
    ::close(pipe_fds[0]);
    ::execl(BAKE_SAVE_LOOP, BAKE_SAVE_LOOP, first.c_str(), second.c_str(), dir.c_str(),
            static_cast<char*>(nullptr));
    ::_exit(127);
  }
  ::close(pipe_fds[1]);
  char ready[6] = {};
  const ssize_t got = ::read(pipe_fds[0], ready, 5);
  ::close(pipe_fds[0]);
  if (got != 5 || std::string(ready) != "ready") {
    ::kill(child, SIGKILL);
    ::waitpid(child, nullptr, 0);
    return -1;
  }
  return child;
}

TEST(BakeDestination, SigkillAtAnyMomentLeavesAWholeLoadableBake) {
  const Scene scene = test::make_room_with_mirror();
  const fs::path dir = fresh_dir("killed") / "bake";
  // The two bakes the killed process alternates between (seeds differ), made once here.
  BakeParams params;
  params.illumination.rays_per_zone_side = 16;
  params.radiosity.ray_budget = 50'000;
  const uint64_t first_seed = params.seed;
  const fs::path first = dir.parent_path() / "first", second = dir.parent_path() / "second";
  save_bake(first.string(), scene, bake_scene(scene, params));
  params.seed += 1;
  save_bake(second.string(), scene, bake_scene(scene, params));
  // Kills spread over a few saves (one takes a few milliseconds), so they land in every
  // phase: writing files, carrying the user's file over, the exchange, removing the old one.
  for (int k = 0; k < 16; ++k) {
    const pid_t child = start_save_loop(first, second, dir);
    ASSERT_GT(child, 0) << "bake_save_loop did not start";
    std::this_thread::sleep_for(std::chrono::microseconds(250 + 700 * k));
    ::kill(child, SIGKILL);
    ::waitpid(child, nullptr, 0);
    if (k == 0) write_text(dir / "render.png", "the user's render");
    const BakeResult loaded = load_bake(dir.string(), scene);
    EXPECT_TRUE(loaded.seed == first_seed || loaded.seed == first_seed + 1)
        << "kill " << k << ": seed " << loaded.seed;
    EXPECT_EQ(read_text(dir / "render.png"), "the user's render") << "kill " << k;
  }
  save_bake(dir.string(), scene, small_bake(scene));
  EXPECT_EQ(entries(dir.parent_path()), (std::vector<std::string>{"bake", "first", "second"}))
      << "a clean save sweeps what the killed ones left";
  EXPECT_EQ(read_text(dir / "render.png"), "the user's render");
}

// Single-file outputs: an image or report lightbake wrote is replaced, anyone else's is not
// (unless --force).
TEST(OutputFiles, RenderReplacesOnlyWhatLightbakeWrote) {
  const fs::path dir = fresh_dir("render_outputs");
  const std::string scene = "'" + test::source_dir() + "/scenes/room.toml'";
  ASSERT_EQ(test::run_lightbake("bake -q " + scene + " -o bake --ray-budget 20000", dir).status, 0);
  const std::string render = "render -q " + scene + " bake --size 8x6 --spp 1 -o ";
  write_text(dir / "photo.png", "the user's photo");
  write_text(dir / "mine.json", "{\"written\": \"by hand\"}");

  test::CliRun run = test::run_lightbake(render + "photo.png", dir);
  EXPECT_EQ(run.status, 1);
  EXPECT_THAT(run.err, HasSubstr("photo.png: exists and was not written by lightbake"));
  EXPECT_EQ(read_text(dir / "photo.png"), "the user's photo");
  EXPECT_FALSE(fs::exists(dir / "photo.json"));
  run = test::run_lightbake(render + "mine.png", dir);  // the report's name is taken too
  EXPECT_THAT(run.err, HasSubstr("mine.json: exists and was not written by lightbake"));

  EXPECT_EQ(test::run_lightbake(render + "out.png", dir).status, 0);
  EXPECT_EQ(test::run_lightbake(render + "out.png", dir).status, 0) << "its own files: replaced";
  EXPECT_EQ(test::run_lightbake(render + "photo.png --force", dir).status, 0);
  EXPECT_NE(read_text(dir / "photo.png"), "the user's photo");
}

}  // namespace
}  // namespace lb
