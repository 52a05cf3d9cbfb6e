// The window driven as an artist drives it, under Xvfb with real X events from xdotool: key
// taps sent in one burst each act once (the GLFW callbacks queue them), an orbit drag stops
// above the floor, fit (F) in the closed room stands inside it, keys typed into the panel's
// Open field go to ImGui and not to the view, an opened file that changes on disk is reloaded
// with the camera kept, and a load error (bad file, missing file) leaves a window that still
// answers and exits 0 when closed. The viewer's --log-actions lines say what each event did.

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "test_helpers.h"

namespace lb {
namespace {

namespace fs = std::filesystem;

bool have_tools() {
  return std::system("command -v xvfb-run > /dev/null 2>&1") == 0 &&
         std::system("command -v xdotool > /dev/null 2>&1") == 0;
}

std::string read_text(const fs::path& path) {
  std::stringstream text;
  text << std::ifstream(path).rdbuf();
  return text.str();
}

struct Driven {
  int status = -1;  // the viewer's exit status
  std::string out, err;
};

// Runs `lightbake view ARGS --log-actions` in the background under Xvfb and `steps` (shell
// lines; $win is the window, wait_for PATTERN FILE waits up to 20 s for a line) beside it,
// then Ctrl+Q; everything inside a 120 s timeout.
Driven drive_view(const fs::path& dir, const std::string& args, const std::string& steps) {
  std::ofstream script(dir / "drive.sh");
  script << "cd '" << dir.string() << "'\n"
         << "wait_for() { i=0; while [ $i -lt 200 ]; do grep -q \"$1\" \"$2\" && return 0; "
            "sleep 0.1; i=$((i+1)); done; echo \"timed out waiting for $1\" >> err; return 1; }\n"
         << "timeout 120 '" << LIGHTBAKE_BINARY_DIR << "/app/lightbake' view " << args
         << " --size 640x480 --log-actions > out 2> err &\n"
         << "pid=$!\n"
         << "win=$(timeout 30 xdotool search --sync --name '^lightbake - ')\n"
         << "xdotool windowfocus $win; sleep 0.3\n"
         << steps << "\n"
         << "xdotool key --window $win ctrl+q\n"
         << "wait $pid; echo $? > status\n";
  script.close();
  const std::string command = test::xvfb_command("sh '" + (dir / "drive.sh").string() + "'");
  std::system(command.c_str());
  Driven run;
  const std::string status = read_text(dir / "status");
  run.status = status.empty() ? -1 : std::stoi(status);
  run.out = read_text(dir / "out");
  run.err = read_text(dir / "err");
  return run;
}

std::vector<std::string> lines_starting(const std::string& text, const std::string& start) {
  std::vector<std::string> lines;
  std::istringstream stream(text);
  for (std::string line; std::getline(stream, line);)
    if (line.rfind(start, 0) == 0) lines.push_back(line);
  return lines;
}

struct Eye {
  float x = NAN, y = NAN, z = NAN;
};
Eye eye_of(const std::string& line) {
  std::smatch match;
  Eye eye;
  if (std::regex_search(line, match, std::regex("eye (\\S+) (\\S+) (\\S+) target"))) {
    eye.x = std::stof(match[1]);
    eye.y = std::stof(match[2]);
    eye.z = std::stof(match[3]);
  }
  return eye;
}

const char* kExtraBox =
    "\n[[objects]]\nname = \"extra\"\nshape = \"box\"\nsize = [0.2, 0.2, 0.2]\n"
    "translate = [1, 0.1, 1]\nmaterial = \"block\"\n";

TEST(ViewerWindowInput, KeysDragTextFieldOpenAndReloadOnSave) {
  if (!have_tools()) GTEST_SKIP() << "needs xvfb-run and xdotool (Debian packages xvfb, xdotool)";
  const fs::path dir = test::fresh_dir("viewer_window_input", "keys_reload");
  fs::copy_file(test::source_dir() + "/scenes/room.toml", dir / "room.toml");
  fs::copy_file(test::source_dir() + "/scenes/room_no_ball.toml", dir / "other.toml");
  const std::string steps =
      // F in the closed room: inside, against the +z wall, looking at the centre.
      "xdotool key f; wait_for '^key f' out\n"
      // Orbit: drag 230 px up from below the panel: -1.38 rad of pitch (0.006 rad/px).
      "xdotool mousemove --window $win 450 470; sleep 0.2\n"
      "xdotool mousedown 1; sleep 0.2; xdotool mousemove --window $win 450 240; sleep 0.2;"
      " xdotool mouseup 1; wait_for '^drag 0' out\n"
      // One burst of taps, 12 ms apart: fewer frames than taps at llvmpipe's frame rate.
      "xdotool key 2 3 Tab Tab h h; wait_for '^key h: HQ off' out\n"
      // The Open field (first in the panel, 67 px down): typing goes to ImGui.
      "xdotool mousemove --window $win 60 67 click 1; wait_for '^text input on' out\n"
      "xdotool type --delay 30 '" +
      (dir / "other.toml").string() +
      "'; xdotool key Return; wait_for '^opened' out\n"
      // Digits in the typed path went to the panel ("key 1: to the panel"): wait for the
      // viewer's own answer.
      "xdotool key 1; wait_for '^key 1: [^t]' out\n"
      // Saved from an editor: a 12-triangle box more.
      "printf '" +
      std::string(kExtraBox) +
      "' >> other.toml; wait_for '^reloaded' out\n"
      "xdotool key 4; wait_for '^key 4' out\n";
  const Driven run = drive_view(dir, "room.toml --no-bake", steps);
  std::printf("%s%s", run.out.c_str(), run.err.c_str());
  EXPECT_EQ(run.status, 0) << run.err;

  const auto fits = lines_starting(run.out, "key f: fit");
  ASSERT_EQ(fits.size(), 1u) << run.out;
  const Eye fitted = eye_of(fits[0]);
  // The room is [-2,2] x [0,3] x [-2,2]: the eye 2% of 2 m off the +z wall at the centre's
  // height (test_view_camera has the same in a unit test).
  EXPECT_NEAR(fitted.z, 1.96f, 1e-3f);
  EXPECT_NEAR(fitted.y, 1.5f, 1e-3f);

  const auto drags = lines_starting(run.out, "drag 0");
  ASSERT_EQ(drags.size(), 1u) << run.out;
  const Eye dragged = eye_of(drags[0]);
  // Pitch -1.38 rad from 1.96 m would put the eye at y = 1.5 - 1.96 sin 1.38 = -0.42 m; the
  // floor stops it 2% of its distance in front: y = 1.5 - 0.98 * 1.5 = 0.03 m.
  EXPECT_NEAR(dragged.y, 0.03f, 1e-3f);
  EXPECT_NEAR(dragged.z, 0.98f * 1.5f / std::tan(1.38f), 2e-3f);

  // Every tap of the burst acted once, in order.
  std::vector<std::string> taps;
  for (const std::string& line : lines_starting(run.out, "key ")) {
    if (line.find("to the panel") != std::string::npos) continue;
    taps.push_back(line.substr(0, line.find(';')));
  }
  const std::vector<std::string> expected_start = {"key f: fit",
                                                   "key 2: direct + constant ambient (Whitted)",
                                                   "key 3: direct + radiosity",
                                                   "key tab: panel hidden",
                                                   "key tab: panel shown",
                                                   "key h: HQ on",
                                                   "key h: HQ off"};
  ASSERT_GE(taps.size(), expected_start.size()) << run.out;
  for (size_t i = 0; i < expected_start.size(); ++i) EXPECT_EQ(taps[i], expected_start[i]);
  // The path typed into the field: its letters went to ImGui (r and h among them), none
  // reloaded or switched HQ.
  EXPECT_FALSE(lines_starting(run.out, "key r: to the panel").empty()) << run.out;
  EXPECT_FALSE(lines_starting(run.out, "key h: to the panel").empty()) << run.out;
  EXPECT_TRUE(lines_starting(run.out, "key r: reload").empty()) << run.out;

  // Opened, then reloaded with the box: its 12 triangles and, where it stands on the floor,
  // the floor's cuts along its footprint (bake/contact_conform.h); the camera where it was.
  const auto opened = lines_starting(run.out, "opened ");
  const auto reloaded = lines_starting(run.out, "reloaded ");
  ASSERT_EQ(opened.size(), 1u) << run.out;
  ASSERT_EQ(reloaded.size(), 1u) << run.out;
  const int before = std::stoi(opened[0].substr(opened[0].rfind(": ") + 2));
  const int after = std::stoi(reloaded[0].substr(reloaded[0].rfind(": ") + 2));
  EXPECT_GE(after - before, 12);
  const auto acted_on = [&](const std::string& key) {
    std::vector<std::string> lines;
    for (const std::string& line : lines_starting(run.out, key))
      if (line.find("to the panel") == std::string::npos) lines.push_back(line);
    return lines;
  };
  const auto ones = acted_on("key 1");
  const auto fours = acted_on("key 4");
  ASSERT_EQ(ones.size(), 1u);
  ASSERT_EQ(fours.size(), 1u);
  EXPECT_EQ(ones[0].substr(ones[0].find("; eye")), fours[0].substr(fours[0].find("; eye")));
}

TEST(ViewerWindowInput, BadFileOnReloadKeepsTheSceneAndTheWindowAnswers) {
  if (!have_tools()) GTEST_SKIP() << "needs xvfb-run and xdotool (Debian packages xvfb, xdotool)";
  const fs::path dir = test::fresh_dir("viewer_window_input", "bad_file");
  fs::copy_file(test::source_dir() + "/scenes/room.toml", dir / "room.toml");
  const std::string steps =
      "echo 'garbage [[[' > room.toml; wait_for 'error' err\n"
      "xdotool key f; wait_for '^key f' out\n";
  const Driven run = drive_view(dir, "room.toml --no-bake", steps);
  std::printf("%s%s", run.out.c_str(), run.err.c_str());
  EXPECT_EQ(run.status, 0) << run.err;
  // One line naming the file and the place.
  const auto errors = lines_starting(run.err, "lightbake: error: ");
  ASSERT_EQ(errors.size(), 1u) << run.err;
  EXPECT_NE(errors[0].find("room.toml:1:"), std::string::npos) << errors[0];
  // The room is still shown: fit stands inside it.
  const auto fits = lines_starting(run.out, "key f: fit");
  ASSERT_EQ(fits.size(), 1u) << run.out;
  EXPECT_NEAR(eye_of(fits[0]).z, 1.96f, 1e-3f);
  EXPECT_TRUE(lines_starting(run.out, "reloaded").empty()) << run.out;
}

TEST(ViewerWindowInput, MissingFileLeavesTheOpenFieldThenOpens) {
  if (!have_tools()) GTEST_SKIP() << "needs xvfb-run and xdotool (Debian packages xvfb, xdotool)";
  const fs::path dir = test::fresh_dir("viewer_window_input", "missing_file");
  fs::copy_file(test::source_dir() + "/scenes/room.toml", dir / "room.toml");
  const std::string steps =
      "wait_for 'error' err\n"
      "xdotool key f; wait_for '^key f' out\n"  // no scene: F is a key like any other
      "xdotool mousemove --window $win 60 67 click 1; wait_for '^text input on' out\n"
      "xdotool type --delay 30 '" +
      (dir / "room.toml").string() +
      "'; xdotool key Return; wait_for '^opened' out\n"
      "xdotool key f; wait_for '^key f: fit' out\n";
  const Driven run = drive_view(dir, "missing.toml --no-bake", steps);
  std::printf("%s%s", run.out.c_str(), run.err.c_str());
  EXPECT_EQ(run.status, 0) << run.err;
  const auto errors = lines_starting(run.err, "lightbake: error: ");
  ASSERT_EQ(errors.size(), 1u) << run.err;
  EXPECT_NE(errors[0].find("missing.toml"), std::string::npos) << errors[0];
  EXPECT_EQ(lines_starting(run.out, "opened ").size(), 1u) << run.out;
  const auto fits = lines_starting(run.out, "key f: fit");
  ASSERT_EQ(fits.size(), 1u) << run.out;
  EXPECT_NEAR(eye_of(fits[0]).z, 1.96f, 1e-3f);
}

// The panel at the default window size: its labels fit (it sizes itself to them), and it
// covers at most a quarter of the width and a third of the view.
TEST(ViewerWindowInput, PanelCoversLessThanAThirdOfA1024x768View) {
  if (std::system("command -v xvfb-run > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "xvfb-run is not installed (Debian package xvfb)";
  const fs::path dir = test::fresh_dir("viewer_window_input", "panel");
  const std::string command = test::xvfb_lightbake_command(
      "view '" + test::source_dir() + "/scenes/room.toml' --no-bake --frames 3 > '" +
      (dir / "out").string() + "'");
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
  const std::string out = read_text(dir / "out");
  std::smatch match;
  ASSERT_TRUE(std::regex_search(
      out, match, std::regex("panel: (\\d+)x(\\d+) px at \\d+,\\d+ in (\\d+)x(\\d+)")))
      << out;
  const double width = std::stod(match[1]), height = std::stod(match[2]);
  const double view_width = std::stod(match[3]), view_height = std::stod(match[4]);
  ASSERT_EQ(view_width, 1024.0);
  ASSERT_EQ(view_height, 768.0);
  std::printf("panel %gx%g px: %.1f%% of the width, %.1f%% of the view\n", width, height,
              100.0 * width / view_width, 100.0 * width * height / (view_width * view_height));
  EXPECT_LE(width, 0.25 * view_width);                        // measured 250 px (24.4%)
  EXPECT_LE(width * height, view_width * view_height / 3.0);  // measured 21%
}

// `snapshot` bakes before it renders (no BAKE_DIR): it says how far the bake is, stage by
// stage in tenths, on stderr (app/console_progress.h adds the time left in stages over 0.5 s).
TEST(SnapshotProgress, PrintsTheBakesProgressWhileItBakes) {
  const fs::path dir = test::fresh_dir("viewer_window_input", "snapshot_progress");
  const test::CliRun run = test::run_lightbake(
      "snapshot '" + test::source_dir() + "/scenes/room.toml' --quality draft --size 64x48 -o '" +
          (dir / "room.png").string() + "'",
      dir.string());
  ASSERT_EQ(run.status, 0) << run.err;
  const auto lines = lines_starting(run.err, "  ");
  int percent_lines = 0, complete_stages = 0;
  for (const std::string& line : lines) {
    if (line.find('%') != std::string::npos) ++percent_lines;
    if (line.find("100%") != std::string::npos) ++complete_stages;
  }
  EXPECT_GE(percent_lines, 20) << run.err;  // measured 36
  EXPECT_GE(complete_stages, 2) << run.err;  // measured 4
}

}  // namespace
}  // namespace lb
