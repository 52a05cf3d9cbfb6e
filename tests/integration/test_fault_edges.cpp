// Fault edges of the lightbake executable (issue 42): a result that cannot be written to stdout
// fails the run, progress that cannot be written does not; a file-size limit or a closed pipe
// is a clean write error; an edited texture makes an old bake refused; a rebake deletes only
// the files a bake writes, whatever its manifest claims; names that are not UTF-8 reach the
// JSON written; an image and its report appear together, the report recording the image's
// hash; an address-space limit too small for a command is refused before the work.
// A newline in a file name stays inside its one-line error. docs/stability.md lists them.

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "bake/io/image_io.h"
#include "bake/io/scene_load.h"
#include "bake/pipeline/bake_io.h"
#include "bake/binary_file.h"
#include "test_helpers.h"

namespace lb {
namespace {

namespace fs = std::filesystem;

// Settings that keep each bake of the Cornell box well under a CPU second.
const std::string kCheap = " --patch-size 0.25 --ray-budget 200000 --soft-gather-rays 1";

std::string box() {
  return "'" + test::source_dir() + "/scenes/cornell_box.toml'";
}

std::string lightbake() {
  return "'" + std::string(LIGHTBAKE_BINARY_DIR) + "/app/lightbake'";
}

size_t lines(const std::string& text) {
  return size_t(std::count(text.begin(), text.end(), '\n'));
}

// Names in `dir` starting with '.': the writers' temporaries.
std::vector<std::string> hidden_entries(const fs::path& dir) {
  std::vector<std::string> names;
  for (const fs::directory_entry& entry : fs::directory_iterator(dir))
    if (entry.path().filename().string().starts_with(".")) names.push_back(entry.path().string());
  return names;
}

nlohmann::json read_json(const fs::path& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

void write_json(const fs::path& path, const nlohmann::json& json) {
  std::ofstream(path) << json.dump(2) << "\n";
}

// The inner redirection wins over run_command's own: stdout goes to /dev/full.
test::CliRun run_to_full_stdout(const std::string& args, const std::string& cwd) {
  return test::run_command("( " + lightbake() + " " + args + " > /dev/full )", cwd);
}

TEST(FaultEdges, AResultThatCannotBeWrittenToStdoutFailsTheRun) {
  const fs::path dir = test::fresh_dir("fault_edges", "stdout");
  Image image(4, 4, 3);
  std::fill(image.pixels.begin(), image.pixels.end(), 0.5f);
  write_exr((dir / "a.exr").string(), image, ExrPixelType::float32);
  for (const std::string& args : {"info " + box(), std::string("compare a.exr a.exr")}) {
    const test::CliRun run = run_to_full_stdout(args, dir.string());
    EXPECT_EQ(run.status, 1) << args;
    EXPECT_NE(run.err.find("lightbake: error: stdout: cannot write the output: No space left"),
              std::string::npos)
        << run.err;
    EXPECT_EQ(lines(run.err), 1u) << run.err;
  }
  // The bake is saved, but its summary on stdout is lost: that is the run's failure.
  const test::CliRun bake =
      run_to_full_stdout("bake -q " + box() + " -o bake" + kCheap, dir.string());
  EXPECT_EQ(bake.status, 1) << bake.err;
  EXPECT_TRUE(fs::exists(dir / "bake" / "manifest.json"));
  // Progress on a stderr that cannot take it is dropped, never fatal.
  const test::CliRun progress = test::run_command(
      "( " + lightbake() + " bake " + box() + " -o bake2" + kCheap + " 2> /dev/full )",
      dir.string());
  EXPECT_EQ(progress.status, 0);
  EXPECT_TRUE(fs::exists(dir / "bake2" / "manifest.json"));
}

// With SIGXFSZ ignored, a write past `ulimit -f` fails with EFBIG: one line, exit 1, no core
// (the signal's default), no temporaries left. 64 KiB is less than a bake's soft_light.exr,
// an export's .glb or a 256 x 256 EXR.
TEST(FaultEdges, AFileSizeLimitIsAWriteErrorWithOneLineAndNoLeftovers) {
  const fs::path dir = test::fresh_dir("fault_edges", "file_size_limit");
  ASSERT_EQ(test::run_lightbake("bake -q " + box() + " -o full" + kCheap, dir.string()).status, 0);
  const std::string limit = "ulimit -c 0; ulimit -f 64; exec ";
  const struct {
    std::string args, output;
  } cases[] = {
      {"bake -q " + box() + " -o bake" + kCheap, "bake"},
      {"export -q " + box() + " full -o scene.glb", "scene.glb"},
      {"render -q " + box() + " -o r.exr --size 256x256 --spp 1" + kCheap, "r.exr"},
  };
  for (const auto& c : cases) {
    const test::CliRun run =
        test::run_command("bash -c \"" + limit + lightbake() + " " + c.args + "\"", dir.string());
    EXPECT_EQ(run.status, 1) << c.args << ": " << run.err;
    EXPECT_NE(run.err.find("File too large"), std::string::npos) << run.err;
    EXPECT_NE(run.err.find(fs::path(c.output).stem().string()), std::string::npos) << run.err;
    EXPECT_EQ(run.err.find(".tmp-"), std::string::npos) << "names a temporary: " << run.err;
    EXPECT_EQ(lines(run.err), 1u) << run.err;
    EXPECT_FALSE(fs::exists(dir / c.output)) << c.args;
    EXPECT_EQ(hidden_entries(dir), std::vector<std::string>()) << c.args;
  }
}

// Issue 42: under `ulimit -v` 600 MB, bake segfaulted and render and export aborted on a
// std::bad_alloc thrown in a worker thread (snapshot died inside OSMesa at lower limits). Each
// is now refused before any work, naming the limit and the need; `info` (517 MiB) still runs.
// Not under AddressSanitizer: its shadow memory needs terabytes of address space, so no
// process starts under such a limit (docs/stability.md).
TEST(FaultEdges, AnAddressSpaceLimitTooSmallIsRefusedBeforeAnyWork) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "AddressSanitizer's shadow memory does not fit under ulimit -v";
#endif
  const fs::path dir = test::fresh_dir("fault_edges", "address_space_limit");
  ASSERT_EQ(test::run_lightbake("bake -q " + box() + " -o full" + kCheap, dir.string()).status, 0);
  const std::string limit = "ulimit -c 0; ulimit -v 600000; exec ";
  const struct {
    std::string args, output;
  } cases[] = {
      {"bake -q " + box() + " -o bake" + kCheap, "bake"},
      {"export -q " + box() + " full -o scene.glb", "scene.glb"},
      {"render -q " + box() + " full -o r.exr --size 64x64 --spp 1", "r.exr"},
      {"snapshot -q " + box() + " full -o s.png --size 64x64 --threads 1", "s.png"},
  };
  for (const auto& c : cases) {
    const test::CliRun run =
        test::run_command("bash -c \"" + limit + lightbake() + " " + c.args + "\"", dir.string());
    EXPECT_EQ(run.status, 1) << c.args << ": " << run.err;
    EXPECT_NE(run.err.find("the address-space limit (ulimit -v) of 586 MiB is below the"),
              std::string::npos)
        << run.err;
    EXPECT_EQ(lines(run.err), 1u) << run.err;
    EXPECT_FALSE(fs::exists(dir / c.output)) << c.args;
  }
  const test::CliRun info =
      test::run_command("bash -c \"" + limit + lightbake() + " info " + box() + "\"", dir.string());
  EXPECT_EQ(info.status, 0) << info.err;
}

// The Cornell box with a UV sphere of `rings` x `rings` quads at `translate` (TOML array).
std::string box_with_ball(int rings, const std::string& translate) {
  return "include = " + box() + "\n[[objects]]\nname = \"dense_ball\"\nshape = \"sphere\"\n" +
         "radius = 0.2\nrings = " + std::to_string(rings) + "\nsegments = " +
         std::to_string(rings) + "\nmaterial = \"white\"\ntranslate = " + translate + "\n";
}

// Issue 42: a scene far bigger than the room passed the per-command check and failed late:
// a 2 M-triangle level under `ulimit -v` 1 GB ran 80 s, then "Embree: building the BVH failed".
// Its triangles now add the bake's per-triangle estimate to the command's need, checked once
// the scene is loaded; `info` (no BVH) still runs under the same limit.
TEST(FaultEdges, ABigSceneOverAnAddressSpaceLimitIsRefusedOnceLoaded) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "AddressSanitizer's shadow memory does not fit under ulimit -v";
#endif
  const fs::path dir = test::fresh_dir("fault_edges", "address_space_big_scene");
  std::ofstream(dir / "big.toml") << box_with_ball(700, "[0, 0.5, 0.7]");  // 0.98 M triangles
  const std::string limit = "ulimit -c 0; ulimit -v 1000000; exec timeout 60 ";
  const test::CliRun run = test::run_command(
      "bash -c \"" + limit + lightbake() + " bake -q big.toml -o bake --threads 2\"", dir.string());
  EXPECT_EQ(run.status, 1) << run.err;
  EXPECT_NE(run.err.find("bake: the address-space limit (ulimit -v) of 977 MiB is below the"),
            std::string::npos)
      << run.err;
  EXPECT_NE(run.err.find("for the 978728 triangles of big.toml"), std::string::npos) << run.err;
  EXPECT_EQ(lines(run.err), 1u) << run.err;
  EXPECT_FALSE(fs::exists(dir / "bake"));
  const test::CliRun info = test::run_command(
      "bash -c \"" + limit + lightbake() + " info big.toml\"", dir.string());
  EXPECT_EQ(info.status, 0) << info.err;
}

// Issue 42: a dense curved mesh through a block cut each of the block's triangles by every
// facet plane crossing it, ~k^2 / 2 pieces: with this 20k-triangle ball the block's 12
// triangles became 1.7 M and loading took 173 s (1 GB); a 2 M-triangle ball exhausted 12 GB.
// The cuts per triangle are now capped (bake/contact_cuts.cpp): bounded pieces, a second.
TEST(FaultEdges, ADenseMeshThroughABlockIsCutIntoBoundedPieces) {
  const fs::path dir = test::fresh_dir("fault_edges", "dense_contact");
  std::ofstream(dir / "ball.toml") << box_with_ball(100, "[0, 0, 0]");
  const test::CliRun run =
      test::run_command("timeout 60 " + lightbake() + " info ball.toml", dir.string());
  ASSERT_EQ(run.status, 0) << run.err;
  std::istringstream listing(run.out);
  std::string line;
  size_t block = 0;
  while (std::getline(listing, line))
    if (line.find("  large_box ") == 0) block = std::stoul(line.substr(line.find_first_of("0123456789")));
  EXPECT_GT(block, 12u) << "the ball still cuts the block along its contact";
  EXPECT_LT(block, 60000u) << run.out;
}

// Issue 42: a newline in a file name split the one-line error in two. Control bytes in a
// message are escaped (\n, \t, \xNN), so a reader taking a line per error sees all of it.
TEST(FaultEdges, ANewlineInAFileNameKeepsTheErrorOnOneLine) {
  const fs::path dir = test::fresh_dir("fault_edges", "newline_in_name");
  std::ofstream(dir / "bad\nname.toml") << "x";
  test::CliRun run =
      test::run_command("bash -c \"" + lightbake() + " info $'bad\\nname.toml'\"", dir.string());
  EXPECT_EQ(run.status, 1);
  EXPECT_EQ(lines(run.err), 1u) << run.err;
  EXPECT_NE(run.err.find("lightbake: error: bad\\nname.toml:1:"), std::string::npos) << run.err;
  run = test::run_command("bash -c \"" + lightbake() + " info $'missing\\x01\\tname.toml'\"",
                          dir.string());
  EXPECT_EQ(run.status, 1);
  EXPECT_EQ(run.err, "lightbake: error: scene file 'missing\\x01\\tname.toml' does not exist\n");
}

// Issue 42: two exports to one name could leave one's .glb with the other's .lightmap.exr,
// both exiting 0, and a reader took the pair. The export now writes its maps first and records
// their FNV-1a in the glTF it renames into place last; a reader refuses a map that is not the
// one its glTF records.
TEST(FaultEdges, AnExportsGltfAndItsLightmapFilesAreOnePair) {
  const fs::path dir = test::fresh_dir("fault_edges", "export_pair");
  ASSERT_EQ(test::run_lightbake("bake -q " + box() + " -o bake" + kCheap, dir.string()).status, 0);
  const std::string exports = "export -q " + box() + " bake --lightmap-format both -o ";
  ASSERT_EQ(test::run_lightbake(exports + "one.glb", dir.string()).status, 0);
  ASSERT_EQ(test::run_lightbake(exports + "two.glb --contents all", dir.string()).status, 0);
  const std::string snapshot = "snapshot -q one.glb --size 32x32 -o s.png --force";
  ASSERT_EQ(test::run_lightbake(snapshot, dir.string()).status, 0);
  // The EXR is read first; without it, the Radiance HDR.
  for (const std::string map : {".lightmap.exr", ".lightmap.hdr"}) {
    if (map == ".lightmap.hdr") fs::remove(dir / "one.lightmap.exr");
    fs::copy_file(dir / ("two" + map), dir / ("one" + map), fs::copy_options::overwrite_existing);
    const test::CliRun run = test::run_lightbake(snapshot, dir.string());
    EXPECT_EQ(run.status, 1) << map;
    EXPECT_NE(run.err.find("one" + map + ": its FNV-1a "), std::string::npos) << run.err;
    EXPECT_NE(run.err.find("that one.glb records: it belongs to another export"),
              std::string::npos)
        << run.err;
    EXPECT_EQ(lines(run.err), 1u) << run.err;
  }
}

// Issue 42: an output folder that takes no file was found only after the work, in a message
// naming a temporary. Now every command probes it first: one line naming the output, nothing
// done (no summary on stdout). Root ignores permissions, so there it is /sys (sysfs refuses).
TEST(FaultEdges, AFolderThatTakesNoFileIsRefusedBeforeAnyWork) {
  const fs::path dir = test::fresh_dir("fault_edges", "read_only_folder");
  fs::path folder = "/sys";
  if (::geteuid() != 0) {
    folder = dir / "read_only";
    fs::create_directories(folder);
    fs::permissions(folder, fs::perms::owner_read | fs::perms::owner_exec);
  }
  const std::string out = "'" + folder.string() + "/out";
  for (const std::string& args :
       {"bake " + box() + " -o " + out + "'" + kCheap,
        "render " + box() + " -o " + out + ".png' --size 16x16 --spp 1" + kCheap,
        "export " + box() + " -o " + out + ".glb'" + kCheap,
        "snapshot " + box() + " -o " + out + ".png' --size 16x16" + kCheap,
        "reference " + box() + " -o " + out + ".exr' --size 16x16 --spp 1"}) {
    const test::CliRun run = test::run_lightbake(args, dir.string());
    EXPECT_EQ(run.status, 1) << args << ": " << run.err;
    EXPECT_NE(run.err.find("out"), std::string::npos) << run.err;
    EXPECT_NE(run.err.find(": cannot write into folder '" + folder.string() + "': "),
              std::string::npos)
        << run.err;
    EXPECT_EQ(lines(run.err), 1u) << run.err;
    EXPECT_EQ(run.out, "") << args;
  }
}

// Issue 42: a disk too full for the output was found after the work. render, reference and
// snapshot now check the folder's free space against the image's estimate (width x height x
// 16 bytes + 64 KiB) first. A full disk needs a small file system: a 128 KiB tmpfs, which only
// root can mount; elsewhere the test skips (docs/stability.md: expected on this machine, whose
// tests run as root).
TEST(FaultEdges, AFolderWithoutSpaceForTheImageIsRefusedBeforeAnyWork) {
  const fs::path dir = test::fresh_dir("fault_edges", "full_disk");
  const fs::path small = dir / "small";
  fs::create_directories(small);
  if (::geteuid() != 0 ||
      test::run_command("mount -t tmpfs -o size=128k tmpfs '" + small.string() + "'").status != 0)
    GTEST_SKIP() << "cannot mount a 128 KiB tmpfs (needs root)";
  ASSERT_EQ(test::run_lightbake("bake -q " + box() + " -o full" + kCheap, dir.string()).status, 0);
  for (const std::string& args :
       {"render " + box() + " -o small/r.exr --size 128x128 --spp 1" + kCheap,
        "reference " + box() + " -o small/x.exr --size 128x128 --spp 1",
        "snapshot " + box() + " -o small/s.png --size 128x128" + kCheap}) {
    const test::CliRun run = test::run_lightbake(args, dir.string());
    EXPECT_EQ(run.status, 1) << args << ": " << run.err;
    EXPECT_NE(run.err.find(": the folder '" + small.string() + "' has "), std::string::npos)
        << run.err;
    EXPECT_NE(run.err.find("free, the output needs about 320 KiB"), std::string::npos) << run.err;
    EXPECT_EQ(lines(run.err), 1u) << run.err;
    EXPECT_EQ(run.out, "") << args;
  }
  // Bake and export: their maps are the atlas's size, known before the first ray (the box's
  // 149 x 1062 texels: 2.5 MiB of bake files, estimated 7 MiB; the export's 4.6 MiB); they
  // were found only at the write. Nothing is written, and pass 1 never got to its maps.
  for (const std::string& args :
       {"bake " + box() + " -o small/bake" + kCheap, "export " + box() + " -o small/e.glb" + kCheap,
        "export " + box() + " full -o small/e.glb"}) {
    const test::CliRun run = test::run_lightbake(args, dir.string());
    EXPECT_EQ(run.status, 1) << args << ": " << run.err;
    EXPECT_NE(run.err.find("free, the output needs about "), std::string::npos) << run.err;
    EXPECT_EQ(run.err.find("illumination maps"), std::string::npos) << run.err;
    EXPECT_EQ(run.out, "") << args;
    EXPECT_TRUE(fs::is_empty(small)) << args;
  }
  // A small image fits: the check refuses only what does not.
  const test::CliRun fits =
      test::run_lightbake("render -q " + box() + " -o small/r.png --size 8x8 --spp 1" + kCheap,
                          dir.string());
  EXPECT_EQ(fits.status, 0) << fits.err;
  test::run_command("umount '" + small.string() + "'");
}

// Issue 42: render and reference wrote the image, then its report; a disk that filled between
// them kept the new image without a report. Under a 1 KiB file-size limit an 8x6 PNG (0.3 KiB)
// fits and its report does not (the reference's, under 1 KiB, is made longer by a long name
// it records twice): the run fails and no image stays.
TEST(FaultEdges, AReportThatCannotBeWrittenLeavesNoNewImage) {
  const fs::path dir = test::fresh_dir("fault_edges", "report_not_written");
  ASSERT_EQ(test::run_lightbake("bake -q " + box() + " -o full" + kCheap, dir.string()).status, 0);
  const std::string limit = "ulimit -c 0; ulimit -f 1; exec ";
  const std::string f = "f" + std::string(100, 'x');
  const struct {
    std::string args, image, report;
  } cases[] = {
      {"render -q " + box() + " full -o r.png --size 8x6 --spp 1", "r.png", "r.json"},
      {"reference -q " + box() + " -o " + f + ".png --size 8x6 --spp 1", f + ".png", f + ".json"},
  };
  for (const auto& c : cases) {
    const test::CliRun run =
        test::run_command("bash -c \"" + limit + lightbake() + " " + c.args + "\"", dir.string());
    EXPECT_EQ(run.status, 1) << c.args << ": " << run.err;
    EXPECT_NE(run.err.find(c.report + ": cannot write: File too large"), std::string::npos)
        << run.err;
    EXPECT_EQ(lines(run.err), 1u) << run.err;
    EXPECT_FALSE(fs::exists(dir / c.image)) << c.args;
    EXPECT_FALSE(fs::exists(dir / c.report)) << c.args;
    EXPECT_EQ(hidden_entries(dir), std::vector<std::string>()) << c.args;
  }
}

std::string file_fnv1a(const fs::path& path) {
  const std::string bytes = test::read_bytes(path.string());
  return fnv1a_hex(std::as_bytes(std::span(bytes.data(), bytes.size())));
}

// A report records its image ("image": {"file", "bytes", "fnv1a"}), a shard's report its data
// ("data"), so a reader tells one run's file with another's report: merge refuses such a shard.
TEST(FaultEdges, AReportRecordsTheHashOfItsImage) {
  const fs::path dir = test::fresh_dir("fault_edges", "report_hash");
  ASSERT_EQ(test::run_lightbake("bake -q " + box() + " -o full" + kCheap, dir.string()).status, 0);
  for (const std::string& args :
       {"render -q " + box() + " full -o r.png --size 8x6 --spp 1",
        "reference -q " + box() + " -o f.exr --size 8x6 --spp 1",
        "render -q " + box() + " full -o s1.rendershard --size 8x6 --spp 1 --shard 0/1 --seed 1",
        "render -q " + box() + " full -o s2.rendershard --size 8x6 --spp 1 --shard 0/1 --seed 2"})
    ASSERT_EQ(test::run_lightbake(args, dir.string()).status, 0) << args;
  // A shard's report records its data the same way (bake/shards/shard_file.h).
  const std::pair<const char*, const char*> records[] = {
      {"r", "image"}, {"f", "image"}, {"s1", "data"}};
  for (const auto& [name, key] : records) {
    const nlohmann::json image = read_json(dir / (std::string(name) + ".json"))[key];
    const fs::path path = dir / image.value("file", std::string("?"));
    ASSERT_TRUE(fs::exists(path)) << name << ": " << image;
    EXPECT_EQ(image["bytes"], fs::file_size(path)) << name;
    EXPECT_EQ(image["fnv1a"], file_fnv1a(path)) << name;
  }
  ASSERT_EQ(test::run_lightbake("merge -q s1.rendershard -o m1.exr", dir.string()).status, 0);
  fs::copy_file(dir / "s2.rendershard", dir / "s1.rendershard",
                fs::copy_options::overwrite_existing);
  const test::CliRun mixed =
      test::run_lightbake("merge -q s1.rendershard -o m2.exr", dir.string());
  EXPECT_EQ(mixed.status, 1);
  EXPECT_NE(mixed.err.find("s1.rendershard: its size or FNV-1a differs from"), std::string::npos)
      << mixed.err;
  EXPECT_EQ(lines(mixed.err), 1u) << mixed.err;
  EXPECT_FALSE(fs::exists(dir / "m2.exr"));
}

// `bake ... 2>&1 | head -1`: the pipe closes after the first progress line; the bake goes on
// and is saved (SIGPIPE ignored, progress dropped). Its stdout summary is lost with the pipe,
// so it exits 1, or 0 when head was still reading.
TEST(FaultEdges, AClosedPipeDoesNotKillABake) {
  const fs::path dir = test::fresh_dir("fault_edges", "closed_pipe");
  const test::CliRun run = test::run_command(
      "bash -c \"" + lightbake() + " bake " + box() + " -o bake" + kCheap +
          " 2>&1 | head -1; exit \\${PIPESTATUS[0]}\"",
      dir.string());
  EXPECT_TRUE(run.status == 0 || run.status == 1) << run.status << " (141: killed by SIGPIPE)";
  EXPECT_TRUE(fs::exists(dir / "bake" / "manifest.json"));
  EXPECT_EQ(hidden_entries(dir), std::vector<std::string>());
}

// The Cornell box with a rug of a 2x2 texture, baked; the texture's pixels change; the old
// bake is refused for the scene as it is now.
TEST(FaultEdges, AnEditedTextureMakesTheOldBakeRefused) {
  const fs::path dir = test::fresh_dir("fault_edges", "edited_texture");
  const auto write_texture = [&](float grey) {
    Image texture(2, 2, 3);
    std::fill(texture.pixels.begin(), texture.pixels.end(), grey);
    write_png((dir / "floor.png").string(), texture);
  };
  write_texture(0.5f);
  std::ofstream(dir / "scene.toml") << "include = " << box() << R"(
[materials.rug]
texture = "floor.png"
[[objects]]
name = "rug"
shape = "quad"
size = [0.5, 0.5]
translate = [0, -0.99, 0]
material = "rug"
)";
  ASSERT_EQ(test::run_lightbake("bake -q scene.toml -o bake" + kCheap, dir.string()).status, 0);
  const std::string render = "render -q scene.toml bake -o r.exr --size 8x8 --spp 1";
  ASSERT_EQ(test::run_lightbake(render, dir.string()).status, 0);

  const std::string hash_before = scene_hash(load_scene((dir / "scene.toml").string()).scene);
  write_texture(0.25f);
  EXPECT_NE(scene_hash(load_scene((dir / "scene.toml").string()).scene), hash_before);
  const test::CliRun stale = test::run_lightbake(render + " --force", dir.string());
  EXPECT_EQ(stale.status, 1);
  EXPECT_NE(stale.err.find("bake/manifest.json: the bake was made for a different scene"),
            std::string::npos)
      << stale.err;
  EXPECT_EQ(lines(stale.err), 1u) << stale.err;

  // A sky image's texels count the same way (it is one of the scene's textures).
  Scene scene = load_scene(test::source_dir() + "/scenes/cornell_box.toml").scene;
  scene.textures.push_back(test::make_rgb_texture(2, 1, [](int, int) { return vec3(1.0f); }));
  scene.sky = Sky{vec3(1.0f), int(scene.textures.size()) - 1};
  const std::string sky_before = scene_hash(scene);
  scene.textures.back().texels[0] = 2.0f;
  EXPECT_NE(scene_hash(scene), sky_before);
}

// A manifest's "files" list is not a licence to delete: a rebake replaces the bake's own fixed
// names only, so the user's files the edited list names stay, bytes and all.
TEST(FaultEdges, ARebakeDeletesOnlyTheFilesABakeWrites) {
  const fs::path dir = test::fresh_dir("fault_edges", "rebake_keeps_user_files");
  const std::string bake = "bake -q " + box() + " -o out" + kCheap;
  ASSERT_EQ(test::run_lightbake(bake, dir.string()).status, 0);
  std::ofstream(dir / "out" / "notes.txt") << "my notes";
  std::ofstream(dir / "out" / "render.exr") << "my render";
  nlohmann::json manifest = read_json(dir / "out" / "manifest.json");
  manifest["files"]["soft_light_exr"] = "notes.txt";
  manifest["files"]["extra"] = "render.exr";
  write_json(dir / "out" / "manifest.json", manifest);

  ASSERT_EQ(test::run_lightbake(bake, dir.string()).status, 0);
  EXPECT_EQ(test::read_bytes((dir / "out" / "notes.txt").string()), "my notes");
  EXPECT_EQ(test::read_bytes((dir / "out" / "render.exr").string()), "my render");
  EXPECT_EQ(read_json(dir / "out" / "manifest.json")["files"]["soft_light_exr"], "soft_light.exr");

  // A bake's own name that is not a regular file is not the bake's: refused, kept.
  fs::remove(dir / "out" / "soft_light.exr");
  fs::create_directory(dir / "out" / "soft_light.exr");
  std::ofstream(dir / "out" / "soft_light.exr" / "mine.txt") << "mine";
  const test::CliRun refused = test::run_lightbake(bake, dir.string());
  EXPECT_EQ(refused.status, 1);
  EXPECT_NE(refused.err.find("soft_light.exr: is not a file a bake wrote"), std::string::npos)
      << refused.err;
  EXPECT_EQ(test::read_bytes((dir / "out" / "soft_light.exr" / "mine.txt").string()), "mine");
}

// File names are bytes: a scene and outputs named with a byte that is not UTF-8 (0xFF) are
// baked, rendered and exported, and the JSON written (manifest, render report, glTF) holds
// U+FFFD for that byte instead of the writer throwing after the work.
TEST(FaultEdges, NamesThatAreNotUtf8AreWrittenToJsonWithAReplacementCharacter) {
  const fs::path dir = test::fresh_dir("fault_edges", "names_not_utf8");
  const std::string ff = "\xff";
  fs::copy_file(test::source_dir() + "/scenes/cornell_box.toml", dir / ("sc" + ff + "ene.toml"));
  const std::string scene = "'sc" + ff + "ene.toml'", bake = "'b" + ff + "k'";
  const struct {
    std::string args, json;
  } cases[] = {
      {"bake -q " + scene + " -o " + bake + kCheap, "b" + ff + "k/manifest.json"},
      {"render -q " + scene + " " + bake + " -o 'r" + ff + ".exr' --size 8x8 --spp 1",
       "r" + ff + ".json"},
      {"export -q " + scene + " " + bake + " -o 'e" + ff + ".gltf'", "e" + ff + ".gltf"},
  };
  for (const auto& c : cases) {
    const test::CliRun run = test::run_lightbake(c.args, dir.string());
    EXPECT_EQ(run.status, 0) << c.args << ": " << run.err;
    ASSERT_TRUE(fs::exists(dir / c.json)) << c.args;
    EXPECT_NO_THROW(read_json(dir / c.json)) << c.json;
  }
  EXPECT_EQ(read_json(dir / ("b" + ff + "k/manifest.json"))["scene"], "sc\uFFFDene.toml");
  EXPECT_EQ(read_json(dir / ("e" + ff + ".gltf"))["scenes"][0]["name"], "sc\uFFFDene");
}

}  // namespace
}  // namespace lb
