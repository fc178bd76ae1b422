// The command line as a user meets it: exit statuses, messages, files.
#include "command_run.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>
#include <fcntl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

namespace {

void expect_bad_input(const std::string& args, const std::string& message) {
  const CommandRun r = run(args);
  EXPECT_EQ(r.status, 2) << args << "\n" << r.output;
  EXPECT_NE(r.output.find(message), std::string::npos) << args << "\n" << r.output;
}

class Cli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() / ("marchcheck_cli_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  // The whole of a file this test's commands wrote, as bytes.
  std::string contents(const std::string& name) const {
    std::ifstream in(path(name), std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  }
  std::filesystem::path dir_;
};

TEST_F(Cli, ScenesListsEveryBuiltin) {
  const CommandRun r = run("scenes");
  EXPECT_EQ(r.status, 0);
  for (const char* name : {"lee-flat", "lee-terrain", "crum-torus", "crum-smooth", "crum-lattice", "crum-mandelbulb",
                           "fogerty", "warped", "flafla-torus", "flafla-csg", "flafla-materials", "flafla-animated"})
    EXPECT_NE(r.output.find(name), std::string::npos) << name;
  EXPECT_EQ(run("scenes --json").status, 0);
}

// Start-up loads none of the libraries only some commands use (Embree, Open MPI, OpenMesh, glslang's ~2.5 ms of
// dynamic loading each, EGL and OpenGL's 1-1.5 ms, OpenImageIO's 160 ms), nor does a PNG render of a scene without
// meshes or a sweep outside an MPI launcher: the dynamic loader's own account (LD_DEBUG=files) names each library as
// it is loaded, and names Embree and OpenImageIO once a mesh scene is rendered to EXR, OpenMesh once a mesh file is
// read, glslang's module once a GLSL field is, EGL once a user's marcher runs on the GL driver. Broken variants: an
// occluder built for every scene (march-occluder-without-meshes), the MPI module loaded before the launcher is asked
// for (commands-mpi-loaded-unlaunched), glslang's module loaded with the sdf library (sdf-glslang-module-at-load),
// the GL driver linked to EGL and OpenGL (gpu-gl-linked), OpenMesh's module loaded with the meshes library
// (meshes-openmesh-at-load).
TEST_F(Cli, StartUpLoadsNoLibraryOnlySomeCommandsUse) {
  const auto loaded = [](const std::string& args) {
    return run_shell("LD_DEBUG=files " + std::string(MARCHCHECK_BINARY) + " " + args).output;
  };
  const std::vector<std::string> commands = {"--help", "render lee-flat --size 16x9 -o " + path("f.png"),
                                             "sweep crum-torus --vary max_steps=8,16 --set width=16 --set height=9"};
  for (const std::string& args : commands) {
    const std::string account = loaded(args);
    ASSERT_NE(account.find("libmarchcheck_march"), std::string::npos) << "the account names what is loaded:\n"
                                                                       << account;
    for (const char* library : {"libmpi", "libembree", "libOpenImageIO", "libmarchcheck_glslang", "libEGL", "libOpenGL",
                                "libGLdispatch", "libOpenMesh"})
      EXPECT_EQ(account.find(library), std::string::npos) << library << " loaded by " << args;
  }
  const std::string mesh = loaded("render flafla-occlusion --size 16x9 -o " + path("m.exr"));
  for (const char* library : {"libembree", "libOpenImageIO"})
    EXPECT_NE(mesh.find(library), std::string::npos) << library << " not loaded where it is used";
  std::ofstream(path("tetra.off")) << "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
  std::ofstream(path("tetra.json")) << R"({"sdf": {"mesh": "tetra.off"}})";
  EXPECT_NE(loaded("render " + path("tetra.json") + " --size 16x9 -o " + path("t.png")).find("libOpenMesh"),
            std::string::npos)
      << "OpenMesh not loaded where a mesh file is read";
  const std::string glsl = loaded("render " + std::string(MARCHCHECK_EXAMPLES) + "/shadertoy_map.glsl --size 16x9 -o " +
                                  path("g.png"));
  EXPECT_NE(glsl.find("libmarchcheck_glslang"), std::string::npos) << "glslang's module not loaded for GLSL";
  const std::string driver =
      loaded("validate " + std::string(MARCHCHECK_TEST_DATA) + "/glsl/user_marcher.glsl --march rayMarch");
  if (driver.find("no GL driver") != std::string::npos) GTEST_SKIP() << driver;
  EXPECT_NE(driver.find("libEGL"), std::string::npos) << "EGL not loaded where the GL driver runs";
}

TEST_F(Cli, RenderWritesTheImageAndTheStats) {
  const CommandRun r = run("render lee-flat --size 64x36 -o " + path("lee.png") + " --aov steps --stats " + path("s.json") +
                    " --set max_steps=50");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_TRUE(std::filesystem::exists(path("lee.png")));
  EXPECT_TRUE(std::filesystem::exists(path("lee.steps.png")));
  const std::string text = contents("s.json");
  for (const char* key : {"\"cost.stages.march.evals\"", "\"cost.stages.march.seconds\"", "\"cost.evals_per_pixel\""})
    EXPECT_NE(text.find(key), std::string::npos) << key;
}

// A seed scene's PNG holds what its shader writes: fogerty's grey 0.7 as 179 (sRGB would write 218), and says so in
// its metadata (read with OpenImageIO's own iinfo, as a user would); a scene set to srgb says that. Broken variant:
// write_render encoding every colour image as sRGB.
TEST_F(Cli, RenderedPngsSayTheirTransferAndHoldIt) {
  ASSERT_EQ(run("render fogerty --size 16x9 -o " + path("f.png")).status, 0);
  const CommandRun linear = run_shell("iinfo -v --stats " + path("f.png"));
  EXPECT_NE(linear.output.find("marchcheck:transfer: \"linear\""), std::string::npos) << linear.output;
  EXPECT_NE(linear.output.find("Stats Max: 255 179 179 (of 255)"), std::string::npos) << linear.output;
  ASSERT_EQ(run("render fogerty --size 16x9 --set output_transfer=srgb -o " + path("s.png")).status, 0);
  const CommandRun srgb = run_shell("iinfo -v --stats " + path("s.png"));
  EXPECT_NE(srgb.output.find("marchcheck:transfer: \"srgb\""), std::string::npos) << srgb.output;
  EXPECT_NE(srgb.output.find("218 218 (of 255)"), std::string::npos) << srgb.output;
}

// A texture_file OpenImageIO cannot read is bad input: render exits 2 naming the material and the file, and writes
// nothing; the GLSL export, which cannot carry an image, refuses such a scene. Broken variant: no check (OIIO's
// texture lookup returns black for an unreadable file, in silence).
TEST_F(Cli, AnUnreadableTextureFileIsBadInput) {
  std::ofstream(path("soil.png")) << "not a png";
  std::ofstream(path("t.json")) << R"({"sdf": {"type": "plane", "normal": [0, 1, 0], "offset": 0, "material": "g"},
    "materials": [{"name": "g", "texture": "planar", "texture_file": "soil.png"}]})";
  const CommandRun r = run("render " + path("t.json") + " --size 16x9 -o " + path("t.png"));
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("material 'g': texture_file '" + path("soil.png") + "': not an image"), std::string::npos)
      << r.output;
  EXPECT_FALSE(std::filesystem::exists(path("t.png")));
  const CommandRun exported = run("scenes --export-glsl " + path("t.json"));
  EXPECT_EQ(exported.status, 2) << exported.output;
  EXPECT_NE(exported.output.find("texture_file"), std::string::npos) << exported.output;
}

// DESIGN's --aov error: the heat map of the colour difference from a reference render, beside the image (it was
// refused as an unknown AOV).
TEST_F(Cli, RenderWritesTheErrorHeatMapAgainstTheReference) {
  const CommandRun r = run("render lee-flat-defect-bias --size 64x36 -o " + path("bias.png") + " --aov error,steps");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_GT(std::filesystem::file_size(path("bias.error.png")), 0u);
  EXPECT_TRUE(std::filesystem::exists(path("bias.steps.png")));
}

TEST_F(Cli, ExportedSceneFileRendersLikeTheBuiltin) {
  const CommandRun exported = run("scenes --export crum-smooth > " + path("smooth.json"));
  ASSERT_EQ(exported.status, 0);
  // PNG: the EXR header carries a timestamp, the PNG holds pixels only.
  ASSERT_EQ(run("render " + path("smooth.json") + " --size 48x27 -o " + path("a.png")).status, 0);
  ASSERT_EQ(run("render crum-smooth --size 48x27 -o " + path("b.png")).status, 0);
  EXPECT_EQ(contents("a.png"), contents("b.png"));
}

TEST_F(Cli, ValidateExitsZeroOnPassOneOnAFailedCheckTwoOnBadInput) {
  const CommandRun ok = run("validate crum-torus --json " + path("v.json"));
  EXPECT_EQ(ok.status, 0) << ok.output;
  EXPECT_NE(ok.output.find("crum-torus: PASS"), std::string::npos);
  const std::string text = contents("v.json");
  EXPECT_NE(text.find("\"hit.false_hit\""), std::string::npos);
  // A scene with a mesh node: the program passes its mesh loader (mesh-icosphere, slower, is in test_validation).
  const CommandRun meshes = run("validate mesh-box");
  EXPECT_EQ(meshes.status, 0) << meshes.output;
  const CommandRun failed = run("validate fogerty-defect-steps");
  EXPECT_EQ(failed.status, 1);
  EXPECT_NE(failed.output.find("hit.undecided"), std::string::npos);
  EXPECT_EQ(run("validate no-such-scene").status, 2);
}

// Issue 7's memory target, measured by the kernel: the peak resident memory of a 3840x2160 render with every
// AOV written, run as its own process (execv, no shell in between, so wait4 reports the renderer itself).
TEST_F(Cli, RenderingFourKWithEveryAovStaysUnderTwoGiB) {
  const std::string output = path("4k.exr");
  std::vector<std::string> args = {MARCHCHECK_BINARY, "render", "lee-flat", "--size", "3840x2160", "--aov",
                                   "depth,normal,steps,evals,id,stages", "-o", output};
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  const pid_t child = ::fork();
  if (child == 0) {
    const int null_fd = ::open("/dev/null", O_WRONLY);
    ::dup2(null_fd, 1);
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  int status = 0;
  rusage usage{};
  ASSERT_EQ(::wait4(child, &status, 0, &usage), child);
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << status;
  const double peak_mib = static_cast<double>(usage.ru_maxrss) / 1024;  // ru_maxrss is in KiB on Linux
  EXPECT_LT(peak_mib, 2048) << "peak " << peak_mib << " MiB";
  EXPECT_GT(peak_mib, 3840.0 * 2160 * 4 / (1 << 20)) << "less than one float per pixel: not the whole render";
  EXPECT_TRUE(std::filesystem::exists(output));
}

// What an estimate is not held to is still printed, with its value, and written to the JSON.
TEST_F(Cli, ValidateShowsTheMetricsAnEstimateIsNotCheckedOn) {
  const CommandRun bulb = run("validate crum-mandelbulb --json " + path("bulb.json"));
  EXPECT_EQ(bulb.status, 0) << bulb.output;
  EXPECT_NE(bulb.output.find("reported, not checked"), std::string::npos) << bulb.output;
  EXPECT_NE(bulb.output.find("normal.angle_p99_deg = "), std::string::npos) << bulb.output;
  const std::string text = contents("bulb.json");
  EXPECT_NE(text.find("\"not_checked\": [\n        \"normal.angle_p99_deg\""), std::string::npos) << text.substr(0, 400);
}

TEST_F(Cli, StabilityExitsZeroAllStableOneOnTheNaiveVariantsTwoOnAnUnwritablePath) {
  const CommandRun ok = run("stability --json " + path("stability.json"));
  EXPECT_EQ(ok.status, 0) << ok.output;
  EXPECT_NE(ok.output.find("grazing.b1e-7"), std::string::npos);
  EXPECT_EQ(ok.output.find("UNSTABLE"), std::string::npos) << ok.output;
  const std::string text = contents("stability.json");
  for (const char* key : {"\"kind\": \"stability\"", "\"criterion\"", "\"clauses\"", "\"breaks\": \"t_zero\"", "\"lipschitz.measured\""})
    EXPECT_NE(text.find(key), std::string::npos) << key;
  const CommandRun naive = run("stability --naive");
  EXPECT_EQ(naive.status, 1);
  EXPECT_NE(naive.output.find("0 of "), std::string::npos) << "every naive variant should be caught";
  const CommandRun bad = run("stability --json " + path("no-such-folder/s.json"));
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.output.find("no-such-folder/s.json"), std::string::npos) << bad.output;
  EXPECT_FALSE(std::filesystem::exists(path("no-such-folder")));
}

TEST_F(Cli, BadInputExitsTwoWithAMessageAndWritesNothing) {
  std::ofstream(path("broken.json")) << "{\n  \"sdf\": {\"type\": \"sphere\" \"radius\": 1}\n}\n";
  std::ofstream(path("no-mesh.json")) << R"({"sdf": {"mesh": "gone.obj"}})";
  struct Case {
    std::string args;
    std::string message;
  };
  const Case cases[] = {
      {"render no-such-scene -o " + path("x.png"), "no-such-scene: not a built-in scene"},
      {"render " + path("missing.json") + " -o " + path("x.png"), "missing.json: cannot open the scene file"},
      {"render " + path("broken.json") + " -o " + path("x.png"), "broken.json:2:35: syntax error"},
      {"render lee-flat --set max_step=3 -o " + path("x.png"), "--set max_step: unknown key"},
      {"render lee-flat --set hit_eps=abc -o " + path("x.png"), "--set hit_eps=abc: expected a number"},
      {"render lee-flat --size 64by36 -o " + path("x.png"), "--size 64by36: expected WIDTHxHEIGHT"},
      // Each side at most 16384: one past it is refused before anything is allocated.
      {"render lee-flat --size 16x16385 -o " + path("x.png"), "--size 16x16385: expected WIDTHxHEIGHT, each 1..16384"},
      {"render lee-flat --size 16385x16 -o " + path("x.png"), "--size 16385x16: expected WIDTHxHEIGHT, each 1..16384"},
      {"render lee-flat --aov colour -o " + path("x.png"), "unknown AOV 'colour'"},
      {"render lee-flat --size 8x8 -o " + path("x.nope"), "x.nope: no image writer"},
      {"frobnicate", "unknown command 'frobnicate'"},
      {"validate " + path("no-mesh.json"), "no-mesh.json: /sdf/mesh: " + path("gone.obj")},
      {"render " + path("no-mesh.json") + " -o " + path("x.png"), "no-mesh.json: /sdf/mesh: " + path("gone.obj")},
  };
  for (const auto& c : cases) expect_bad_input(c.args, c.message);
  EXPECT_FALSE(std::filesystem::exists(path("x.png")));
  for (const auto& entry : std::filesystem::directory_iterator(dir_))
    EXPECT_EQ(entry.path().filename().string().find(".tmp"), std::string::npos) << entry.path();
}

TEST_F(Cli, SweepWritesEveryCombinationAndRejectsBadAxes) {
  const CommandRun r = run("sweep crum-torus --vary max_steps=4,64 --vary marcher=sphere,relaxed --repeat 1 --width 32 "
                           "--target hit.undecided=0.01 --json " + path("s.json") + " --csv " + path("s.csv"));
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("cheapest meeting the target"), std::string::npos) << r.output;
  std::ifstream csv(path("s.csv"));
  std::string line;
  int rows = 0;
  while (std::getline(csv, line)) ++rows;
  EXPECT_EQ(rows, 5);  // header + 2 x 2 combinations
  for (const auto& [args, message] : std::vector<std::pair<std::string, std::string>>{
           {"sweep crum-torus --vary max_steps=4,lots", "--vary max_steps=lots: expected a number"},
           {"sweep crum-torus --vary max_step=4", "--vary max_step: unknown key"},
           {"sweep crum-torus --vary max_steps=4 --width 16 --repeat 1 --target no.such=1", "--target no.such"},
           {"sweep crum-torus --vary max_steps=4 --repeat 0", "--repeat 0"}}) {
    const CommandRun bad = run(args);
    EXPECT_EQ(bad.status, 2) << args << "\n" << bad.output;
    EXPECT_NE(bad.output.find(message), std::string::npos) << args << "\n" << bad.output;
  }
}

// A result file without its wall times (cost.seconds, each stage's seconds, and the seconds front that follows
// from them): the only fields in which two runs of the same work may differ.
std::string without_wall_times(const std::string& text) {
  const auto strip = [](auto& self, nlohmann::ordered_json& j) -> void {
    if (j.is_array())
      for (auto& e : j) self(self, e);
    if (!j.is_object()) return;
    for (auto it = j.begin(); it != j.end();) {
      if (it.key().ends_with("seconds")) {
        it = j.erase(it);
      } else {
        self(self, it.value());
        ++it;
      }
    }
  };
  nlohmann::ordered_json j = nlohmann::ordered_json::parse(text);
  strip(strip, j);
  return j.dump(1);
}

// 12 combinations of a small crum-torus: about 0.1 s each.
const std::string kShardedSweep = "sweep crum-torus --vary marcher=sphere,relaxed --vary hit_eps=1e-3,1e-4 --vary "
                                  "max_steps=32,64,128 --set width=64 --set height=36 --repeat 1 --width 64";

TEST_F(Cli, ASweepInShardsMergesIntoTheSingleProcesssFile) {
  ASSERT_EQ(run(kShardedSweep + " --json " + path("single.json")).status, 0);
  for (int i = 0; i < 3; ++i) {
    const CommandRun shard = run(kShardedSweep + " --shard " + std::to_string(i) + "/3 --json " + path("s" + std::to_string(i)));
    ASSERT_EQ(shard.status, 0) << shard.output;
    EXPECT_NE(shard.output.find("4 of 12 combinations"), std::string::npos) << shard.output;
  }
  // In any order: the merge orders by index.
  const CommandRun merged = run("merge " + path("s2") + " " + path("s0") + " " + path("s1") + " -o " + path("merged.json"));
  ASSERT_EQ(merged.status, 0) << merged.output;
  EXPECT_NE(merged.output.find("crum-torus: 12 combinations"), std::string::npos) << merged.output;
  ASSERT_FALSE(contents("merged.json").empty());
  EXPECT_EQ(without_wall_times(contents("merged.json")), without_wall_times(contents("single.json")));
  EXPECT_EQ(run("compare " + path("single.json") + " " + path("merged.json")).status, 0);

  // Refused, writing nothing: a missing shard, and a shard of another configuration (another time of the scene).
  expect_bad_input("merge " + path("s0") + " " + path("s2") + " -o " + path("none.json"), "shard 1/3 is missing (4 items)");
  ASSERT_EQ(run(kShardedSweep + " --set time=1 --shard 1/3 --json " + path("other")).status, 0);
  expect_bad_input("merge " + path("s0") + " " + path("other") + " " + path("s2") + " -o " + path("none.json"),
                   path("other") + ": not from the same run as " + path("s0") + ": its scenes differ");
  expect_bad_input("merge " + path("s0") + " " + path("s0") + " -o " + path("none.json"), "are both shard 0/3");
  expect_bad_input("merge " + path("single.json"), "not a shard file");
  EXPECT_FALSE(std::filesystem::exists(path("none.json")));
  expect_bad_input(kShardedSweep + " --shard 1/3", "--shard 1/3: needs --json FILE");
  expect_bad_input(kShardedSweep + " --shard 3/3 --json " + path("x"), "the index must be below 3");
}

TEST_F(Cli, AValidateInShardsMergesIntoTheSingleProcesssTableFileAndStatus) {
  // One scene fails (the defect variant): the status, as the table and the file, is the whole run's.
  const std::string scenes = "validate crum-torus crum-torus-defect-fov lee-flat";
  const CommandRun single = run(scenes + " --json " + path("single.json"));
  ASSERT_EQ(single.status, 1) << single.output;
  EXPECT_EQ(run(scenes + " --shard 0/2 --json " + path("v0")).status, 0);
  EXPECT_EQ(run(scenes + " --shard 1/2 --json " + path("v1")).status, 1);  // holds the defect variant
  const CommandRun merged = run("merge " + path("v1") + " " + path("v0") + " -o " + path("merged.json"));
  EXPECT_EQ(merged.status, 1) << merged.output;
  EXPECT_EQ(merged.output, single.output);
  EXPECT_EQ(without_wall_times(contents("merged.json")), without_wall_times(contents("single.json")));
  expect_bad_input("merge " + path("v0") + " " + path("v1") + " --csv " + path("v.csv"), "a validate run has no CSV");
}

#ifdef MARCHCHECK_MPIRUN
// mpirun as CI runs it: as root, more ranks than cores, shared memory only.
const std::string kMpirun = std::string(MARCHCHECK_MPIRUN) + " --allow-run-as-root --oversubscribe --mca btl self,vader ";

TEST_F(Cli, ASweepUnderMpirunWritesTheSingleProcesssFileFromRankZero) {
  const std::string marchcheck = std::string(MARCHCHECK_BINARY) + " ";
  ASSERT_EQ(run(kShardedSweep + " --json " + path("single.json")).status, 0);
  const CommandRun ranks = run_shell(kMpirun + "-n 3 " + marchcheck + kShardedSweep + " --json " + path("mpi.json"));
  ASSERT_EQ(ranks.status, 0) << ranks.output;
  EXPECT_EQ(without_wall_times(contents("mpi.json")), without_wall_times(contents("single.json")));
  // One rank of another configuration, or one that fails, fails the run with its message and writes nothing.
  const CommandRun other = run_shell(kMpirun + "-n 2 " + marchcheck + kShardedSweep + " --json " + path("bad.json") +
                                     " : -n 1 " + marchcheck + kShardedSweep + " --set time=1 --json " + path("bad.json"));
  EXPECT_EQ(other.status, 2) << other.output;
  EXPECT_NE(other.output.find("rank 2: not from the same run as rank 0: its scenes differ"), std::string::npos) << other.output;
  const CommandRun failed = run_shell(kMpirun + "-n 2 " + marchcheck + kShardedSweep + " --json " + path("bad.json") +
                                      " : -n 1 " + marchcheck + kShardedSweep + " --set width=0 --json " + path("bad.json"));
  EXPECT_EQ(failed.status, 2) << failed.output;
  EXPECT_NE(failed.output.find("marchcheck sweep: rank 2: --set width"), std::string::npos) << failed.output;
  EXPECT_FALSE(std::filesystem::exists(path("bad.json")));
}
#else
TEST_F(Cli, AnMpiLaunchOfABuildWithoutMpiIsRefused) {
  const CommandRun r = run_shell("OMPI_COMM_WORLD_SIZE=3 " + std::string(MARCHCHECK_BINARY) + " " + kShardedSweep);
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("built without MPI, so each would do the whole run"), std::string::npos) << r.output;
}
#endif

TEST_F(Cli, CompareExitsOneOnAWorseMetricZeroOnTheSameFileTwoOnBadInput) {
  ASSERT_EQ(run("validate crum-torus --json " + path("base.json")).status, 0);
  EXPECT_EQ(run("compare " + path("base.json") + " " + path("base.json")).status, 0);
  // The same scene marched with a quarter of the steps: more undecided rays and a failing check.
  ASSERT_EQ(run("validate crum-torus --set max_steps=6 --json " + path("worse.json")).status, 1);
  const CommandRun worse = run("compare " + path("base.json") + " " + path("worse.json"));
  EXPECT_EQ(worse.status, 1) << worse.output;
  EXPECT_NE(worse.output.find("REGRESSION"), std::string::npos) << worse.output;
  EXPECT_NE(worse.output.find("crum-torus: hit.undecided"), std::string::npos) << worse.output;
  std::ofstream(path("junk.json")) << "{\"kind\": 3}";
  const CommandRun junk = run("compare " + path("base.json") + " " + path("junk.json"));
  EXPECT_EQ(junk.status, 2);
  EXPECT_NE(junk.output.find("junk.json"), std::string::npos) << junk.output;
  EXPECT_EQ(run("compare " + path("base.json") + " " + path("nope.json")).status, 2);
}

// One scene file per bad-input class: each names the file, the place (line:column or JSON path) and what was
// expected, and exits 2 before anything is written.
TEST_F(Cli, BadSceneFilesExitTwoNamingTheFileThePlaceAndTheProblem) {
  const std::string sphere = R"("sdf": {"type": "sphere", "radius": 1})";
  std::string deep = R"({"sdf": )";
  for (int i = 0; i < 10000; ++i) deep += R"({"type": "round", "radius": 0, "child": )";
  deep += R"({"type": "sphere", "radius": 1})" + std::string(10001, '}');
  struct Case {
    std::string name, text, message;
  };
  const Case cases[] = {
      {"syntax", "{\n  \"sdf\": {\"type\": \"sphere\", \"radius\": 1,}\n}\n", "syntax.json:2:41: syntax error"},
      {"truncated", "{\"sdf\": {\"type\": \"sphere\"", "truncated.json:1:26: syntax error"},
      {"unknown-key", R"({"max_step": 3, )" + sphere + "}", "unknown-key.json: /max_step: unknown key; expected one of"},
      {"unknown-type", R"({"sdf": {"type": "blob"}})", "unknown-type.json: /sdf/type: unknown type 'blob'; expected one of"},
      {"wrong-type", R"({"sdf": {"type": "sphere", "radius": [1]}})",
       "wrong-type.json: /sdf/radius: expected a number, got array"},
      {"negative-radius", R"({"sdf": {"type": "sphere", "radius": -1}})",
       "negative-radius.json: /sdf/radius: value -1 is out of range [1e-12, 1e+300]"},
      {"zero-eps", R"({"hit_eps": 0, )" + sphere + "}", "zero-eps.json: /hit_eps: value 0 is out of range (0, 1e+06]"},
      {"negative-steps", R"({"max_steps": -5, )" + sphere + "}",
       "negative-steps.json: /max_steps: value -5 is out of range [0, 1.67772e+07]"},
      {"nan", R"({"hit_eps": NaN, )" + sphere + "}", "nan.json:1:13: syntax error"},
      {"deep", deep, "deep.json: /sdf/child/child/"},
      {"bad-mesh-index", R"({"meshes": [{"vertices": [[0,0,0],[1,0,0],[0,1,0]], "triangles": [[0,1,3]]}], )" + sphere + "}",
       "bad-mesh-index.json: /meshes/0/triangles/0/2: value 3 is out of range [0, 2]"},
  };
  for (const auto& c : cases) {
    std::ofstream(path(c.name + ".json"), std::ios::binary) << c.text;
    const CommandRun r = run("render " + path(c.name + ".json") + " --size 8x8 -o " + path("x.png"));
    EXPECT_EQ(r.status, 2) << c.name << "\n" << r.output;
    EXPECT_NE(r.output.find(c.message), std::string::npos) << c.name << "\n" << r.output;
    EXPECT_EQ(r.output.rfind("marchcheck render: " + path(c.name + ".json"), 0), 0u) << r.output;
  }
  EXPECT_NE(run("render " + path("deep.json") + " -o " + path("x.png")).output.find("nests deeper than 64 levels"),
            std::string::npos);
  EXPECT_FALSE(std::filesystem::exists(path("x.png")));
}

// Mesh files a scene names: each broken file is refused with its name and the problem, status 2, nothing written.
TEST_F(Cli, BadMeshFilesInASceneExitTwoNamingTheMeshFile) {
  static const char kGarbage[] = "\x7f\x45\x4c\x46\x02\x01\x01\x00 not a mesh";  // an ELF header, a NUL inside
  struct Case {
    std::string file, text, message;
  };
  const Case cases[] = {
      {"truncated.off", "OFF\n4 4 0\n0 0 0\n1 0 0\n", "truncated.off"},
      {"garbage.obj", std::string(kGarbage, sizeof kGarbage - 1), "garbage.obj"},
      {"nan.obj", "v 0 0 0\nv 1 0 0\nv nan 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n", "nan.obj"},
      {"index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 9\n", "index.obj"},
      // A box whose corner 8 is pushed down through the bottom: closed and manifold, but it has no single inside
      // (rendered with status 0 before the crossing test).
      {"folded.obj",
       "v -1 -1 -1\nv 1 -1 -1\nv -1 1 -1\nv 1 1 -1\nv -1 -1 1\nv 1 -1 1\nv -1 1 1\nv 0.5 -3 0.5\n"
       "f 1 3 4\nf 1 4 2\nf 5 6 8\nf 5 8 7\nf 1 2 6\nf 1 6 5\nf 3 7 8\nf 3 8 4\nf 1 5 7\nf 1 7 3\nf 2 4 8\nf 2 8 6\n",
       "folded.obj': self-intersecting: 6 pairs of triangles"},
  };
  for (const auto& c : cases) {
    std::ofstream(path(c.file), std::ios::binary) << c.text;
    std::ofstream(path("scene.json")) << R"({"sdf": {"mesh": ")" << c.file << R"("}})";
    const CommandRun r = run("render " + path("scene.json") + " --size 8x8 -o " + path("x.png"));
    EXPECT_EQ(r.status, 2) << c.file << "\n" << r.output;
    EXPECT_NE(r.output.find("scene.json: /sdf/mesh: "), std::string::npos) << c.file << "\n" << r.output;
    EXPECT_NE(r.output.find(c.message), std::string::npos) << c.file << "\n" << r.output;
    // The same from the scene's own folder with a bare file name (a path with no folder part).
    const CommandRun here = run_shell("cd " + dir_.string() + " && " + MARCHCHECK_BINARY + " render scene.json --size 8x8 -o x.png");
    EXPECT_EQ(here.status, 2) << c.file << "\n" << here.output;
    // The mesh by its full path: bare when the loader names it, quoted when the mesh checks do.
    EXPECT_TRUE(here.output.find("scene.json: /sdf/mesh: " + path(c.file)) != std::string::npos ||
                here.output.find("scene.json: /sdf/mesh: '" + path(c.file) + "'") != std::string::npos)
        << here.output;
  }
  EXPECT_FALSE(std::filesystem::exists(path("x.png")));
}

// A weld is said where the user reads the result: render's output names the mesh and what the weld changed.
TEST_F(Cli, RenderSaysWhatAWeldChanged) {
  std::string obj = "v -1 -1 -1\nv 1 -1 -1\nv -1 1 -1\nv 1 1 -1\nv -1 -1 1\nv 1 -1 1\nv -1 1 1\nv 1 1 1\nv 1 1 1\n"
                    "f 1 3 4\nf 1 4 2\nf 5 6 8\nf 5 8 7\nf 1 2 6\nf 1 6 5\nf 3 7 8\nf 3 8 4\nf 1 5 7\nf 1 7 3\n"
                    "f 2 4 8\nf 2 9 6\n";
  for (int i = 0; i < 200; ++i) obj += "f 8 9 4\n";
  std::ofstream(path("seam.obj")) << obj;
  std::ofstream(path("seam.json")) << R"({"camera": {"position": [3, 2, 4]}, "sdf": {"mesh": "seam.obj", "weld": 1e-9}})";
  const CommandRun r = run("render " + path("seam.json") + " --size 16x9 -o " + path("seam.png"));
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("seam: mesh '" + path("seam.obj") + "' welded at 1e-09: 1 vertices merged, 200 faces"),
            std::string::npos)
      << r.output;
}

TEST_F(Cli, BadArgumentsExitTwoWithAMessage) {
  struct Case {
    std::string args, message;
  };
  const Case cases[] = {
      {"render lee-flat --frobnicate", "The following argument was not expected: --frobnicate"},
      {"render", "scene is required"},
      {"render lee-flat --set max_steps -o " + path("x.png"), "--set max_steps: expected KEY=VALUE"},
      {"render lee-flat --set hit_eps=0 -o " + path("x.png"), "--set hit_eps=0: value 0 is out of range (0, 1e+06]"},
      {"render lee-flat --set hit_eps=nan -o " + path("x.png"), "--set hit_eps=nan: expected a number, got NaN"},
      {"render lee-flat --set max_steps=-1 -o " + path("x.png"), "--set max_steps=-1: value -1 is out of range"},
      {"render lee-flat --set marcher=warp -o " + path("x.png"), "'warp' is not one of sphere, relaxed, fixed, scaled"},
      {"render lee-flat --size 0x10 -o " + path("x.png"), "--size 0x10: expected WIDTHxHEIGHT, each 1..16384"},
      {"render lee-flat --size 99999999999x10 -o " + path("x.png"), "--size 99999999999x10: expected WIDTHxHEIGHT"},
      {"render lee-flat --size 64x36x2 -o " + path("x.png"), "--size 64x36x2: expected WIDTHxHEIGHT"},
      {"validate lee-flat --set nope=1", "marchcheck validate: --set nope: unknown key; expected one of"},
  };
  for (const auto& c : cases) expect_bad_input(c.args, c.message);
  EXPECT_FALSE(std::filesystem::exists(path("x.png")));
}

TEST_F(Cli, AFailedWriteKeepsThePreviousFileAndLeavesNoTemporary) {
  // The image writer fails (no writer for the extension) after the render: the old file stays as it was.
  std::ofstream(path("old.nope")) << "previous image";
  const CommandRun image = run("render lee-flat --size 8x8 -o " + path("old.nope"));
  EXPECT_EQ(image.status, 2) << image.output;
  EXPECT_NE(image.output.find(path("old.nope") + ": no image writer"), std::string::npos) << image.output;
  EXPECT_EQ(contents("old.nope"), "previous image");
  // The stats go where a non-empty folder is in the way: the rename fails, status 2, the folder is untouched.
  std::filesystem::create_directories(path("stats.json/inside"));
  const CommandRun stats = run("render lee-flat --size 8x8 -o " + path("new.png") + " --stats " + path("stats.json"));
  EXPECT_EQ(stats.status, 2) << stats.output;
  EXPECT_NE(stats.output.find(path("stats.json") + ": cannot move the finished file into place"), std::string::npos)
      << stats.output;
  EXPECT_TRUE(std::filesystem::is_directory(path("stats.json/inside")));
  // A folder that does not exist: nothing is created.
  const CommandRun missing = run("render lee-flat --size 8x8 -o " + path("no/such/dir/x.png"));
  EXPECT_EQ(missing.status, 2) << missing.output;
  EXPECT_NE(missing.output.find(path("no/such/dir/x.png") + ": cannot create"), std::string::npos) << missing.output;
  EXPECT_NE(missing.output.find("(missing folder or no permission?)"), std::string::npos) << missing.output;
  EXPECT_FALSE(std::filesystem::exists(path("no")));
  for (const auto& entry : std::filesystem::directory_iterator(dir_))
    EXPECT_EQ(entry.path().filename().string().find(".tmp"), std::string::npos) << entry.path();
}

}  // namespace

namespace {

// A GLSL file alone validates as the GPU runs it (float) and as its reference (double): the feature tour (helpers,
// an overload, p.xz *= mat2, a loop with break, inout, #define, a struct, iTime) passes both.
TEST_F(Cli, AGlslFileAloneValidatesInFloatAndDouble) {
  const CommandRun r = run("validate " + std::string(MARCHCHECK_TEST_DATA) + "/glsl/feature_tour.glsl");
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("feature_tour (float): PASS"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("feature_tour (double): PASS"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("hit.false_hit"), std::string::npos) << "the usual table";
  EXPECT_NE(r.output.find("scene: GLSL field map of"), std::string::npos) << "the scene made for it, stated";
  EXPECT_NE(r.output.find("camera framing the region where it is negative, ["), std::string::npos) << r.output;
}

// The line of a check in validate's table.
std::string check_line(const std::string& output, const std::string& check) {
  const size_t at = output.find("  " + check + " ");
  return at == std::string::npos ? "" : output.substr(at, output.find('\n', at) - at);
}

// GLSL's mediump (precision=half) on the feature tour: binary16 spaces values 2^-9 apart near |p| = 2 to 4, wider
// than the default normal epsilon (1e-3), so central differences collapse and normals miss by over 5 degrees at
// p99 where float's are within 2; hits still pass. Broken variants: Half without its rounding
// (glsl-half-unrounded), the half flag ignored (glsl-half-ignored) or not set by --set
// (sdf-precision-half-not-applied): the run is float's and passes.
TEST_F(Cli, HalfPrecisionModelsMediumpAndItsNormalsFail) {
  const std::string file = std::string(MARCHCHECK_TEST_DATA) + "/glsl/feature_tour.glsl";
  const CommandRun r = run("validate " + file + " --set precision=half");
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_NE(r.output.find("feature_tour (half): FAIL"), std::string::npos) << r.output;
  const std::string normals = check_line(r.output, "normal.angle_p99_deg");
  EXPECT_NE(normals.find("FAIL"), std::string::npos) << r.output;
  EXPECT_GT(std::atof(normals.c_str() + normals.find_first_of("0123456789")), 5) << normals;
  for (const char* check : {"hit.false_hit", "hit.false_miss", "hit.overshoot"})
    EXPECT_NE(check_line(r.output, check).find("pass"), std::string::npos) << check << "\n" << r.output;
  expect_bad_input("validate " + std::string(MARCHCHECK_TEST_DATA) + "/glsl/user_marcher.glsl --march rayMarch "
                   "--set precision=half", "--march judges the GL driver's run, in float; the marcher in half");
  expect_bad_input("validate " + file + " --set precision=quad",
                   "--set precision=quad: 'quad' is not one of float, double, half");
  std::ofstream(path("half.json")) << R"({"name": "h", "sdf": {"type": "glsl", "code": "float map(vec3 p) { return )"
                                      R"(length(p) - 1.0; }", "kind": "exact", "precision": "quarter"}})";
  expect_bad_input("validate " + path("half.json"), "/precision: expected float or half");
}

// A field that claims a bound but is 1.5 times steeper is caught: marched in steps of f / L with its declared
// L = 1, steps land inside the sphere (hit.overshoot: the march went through the first surface); declared with its
// constant, the same field passes. (Seen from farther than 4, a first step of 1.5 times the distance jumps this
// sphere whole, for the marcher and for the numerical reference, whose steps trust the same L: that hole is issue
// 15's, the certified reference's. From 2.3 away, both land inside.)
TEST_F(Cli, AGlslFieldThatBreaksItsDeclaredBoundFails) {
  const std::string code = "float map(vec3 p) { return (length(p - vec3(0.0, 1.0, 0.0)) - 1.0) * 1.5; }";
  for (const auto& [kind, status] : {std::pair{std::string("\"kind\": \"bound\""), 1},
                                     std::pair{std::string("\"kind\": \"lipschitz\", \"lipschitz\": 1.5"), 0}}) {
    std::ofstream(path("steep.json")) << R"({"camera": {"position": [0, 1.5, 3.2], "target": [0, 1, 0]},)"
                                      << R"( "sdf": {"type": "glsl", "code": ")" << code << "\", " << kind << "}}";
    const CommandRun r = run("validate " + path("steep.json") + " --set marcher=scaled");  // steps of f / L
    EXPECT_EQ(r.status, status) << kind << "\n" << r.output;
    EXPECT_EQ(check_line(r.output, "hit.overshoot").find("FAIL") != std::string::npos, status == 1) << r.output;
  }
}

TEST_F(Cli, AGlslFileThatDoesNotCompileIsBadInputNamingTheLine) {
  std::ofstream(path("bad.glsl")) << "float map(vec3 p) {\n  return length(q) - 1.0;\n}\n";
  expect_bad_input("validate " + path("bad.glsl"), path("bad.glsl") + ":2: 'q' : undeclared identifier");
  std::ofstream(path("map.glsl")) << "float map(vec3 p) { return length(p) - 1.0; }\n";
  expect_bad_input("validate " + path("map.glsl") + " --function sdf", "no function sdf(vec3)");
}

// A user's own marcher on the GL driver (tests/data/glsl/user_marcher.glsl), judged by validate's checks: the right
// one passes, and each marcher with a known bug fails the check that bug breaks, and no other of those four.
// rayMarchRelaxed is the control of rayMarchSignedHit: the same over-relaxed steps, with the hit test on |f|.
TEST_F(Cli, AUserMarcherOnTheDriverPassesAndEachKnownBugIsCaught) {
  const std::string file = std::string(MARCHCHECK_TEST_DATA) + "/glsl/user_marcher.glsl";
  struct Variant {
    const char* march;
    const char* breaks;  // the check it fails, or nullptr
  };
  const Variant variants[] = {{"rayMarch", nullptr},
                              {"rayMarchUnnormalised", "hit.false_hit"},
                              {"rayMarchOffByOne", "march.over_max_steps"},
                              {"rayMarchSignedHit", "hit.overshoot"},
                              {"rayMarchRelaxed", nullptr}};
  for (const Variant& v : variants) {
    const CommandRun r = run("validate " + file + " --march " + v.march + " --normal calcNormal");
    if (r.status == 2 && r.output.find("no GL driver") != std::string::npos) GTEST_SKIP() << r.output;
    EXPECT_EQ(r.status, v.breaks ? 1 : 0) << v.march << "\n" << r.output;
    for (const char* check : {"hit.false_hit", "march.over_max_steps", "hit.overshoot", "normal.angle_p99_deg"}) {
      const bool failed = check_line(r.output, check).find("FAIL") != std::string::npos;
      EXPECT_EQ(failed, v.breaks && std::string(v.breaks) == check) << v.march << " " << check << "\n" << r.output;
    }
    EXPECT_NE(r.output.find("limits from the shader: MAX_STEPS = 64 (max_steps) MAX_DIST = 30 (max_dist) "
                            "SURF_DIST = 0.001 (hit_eps)"),
              std::string::npos)
        << r.output;
    EXPECT_NE(r.output.find("map calls counted, on "), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("driver against CPU (the same marcher, float): 0 rays with another outcome"),
              std::string::npos)
        << r.output;
    // The marcher in binary16 (mediump) on the CPU: t moves by more than half's unit roundoff, 2^-11 (a run left
    // in float moves it by 0: commands-user-half-as-float), and by less than 10%.
    const std::string half = "against half (mediump): ";
    const size_t at = r.output.find(half);
    ASSERT_NE(at, std::string::npos) << r.output;
    const double relative = std::atof(r.output.c_str() + r.output.find("t within ", at) + 9);
    EXPECT_GT(relative, 0x1p-11) << r.output;
    EXPECT_LT(relative, 0.1) << r.output;
  }
}

TEST_F(Cli, AUserMarcherThatIsNotThereOrHasNoDriverIsBadInput) {
  const std::string file = std::string(MARCHCHECK_TEST_DATA) + "/glsl/user_marcher.glsl";
  expect_bad_input("validate " + file + " --march rayMarchTypo",
                   file + ": no marcher rayMarchTypo(vec3 ro, vec3 rd) returning float");
  expect_bad_input("validate lee-flat --march rayMarch", "lee-flat: --march runs a .glsl file's own marcher");
  const CommandRun r = run_shell("__EGL_VENDOR_LIBRARY_FILENAMES=/nonexistent " + std::string(MARCHCHECK_BINARY) +
                                 " validate " + file + " --march rayMarch");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find(file + ": no GL driver to run the marcher on: "), std::string::npos) << r.output;
}

// The shader's own parameters as sweep axes: a #define rewritten per combination changes what its marcher does
// (a smaller SURF_DIST: smaller t errors, more map calls per ray); a name the shader has neither as a #define nor
// as a uniform, or an axis not of the shader's, is bad input. Broken variant: an override that did not reach the
// shader would give equal rows.
TEST_F(Cli, SweepVariesAUserMarchersOwnDefines) {
  const std::string file = std::string(MARCHCHECK_TEST_DATA) + "/glsl/user_marcher.glsl";
  const CommandRun r =
      run("sweep " + file + " --march rayMarch --normal calcNormal --vary glsl.SURF_DIST=0.01,0.0001");
  if (r.status == 2 && r.output.find("no GL driver") != std::string::npos) GTEST_SKIP() << r.output;
  ASSERT_EQ(r.status, 0) << r.output;
  // Each row: SURF_DIST, hit.t_err_p99, 5 counts, cost.evals_per_pixel (map calls per ray), ...
  std::map<std::string, std::pair<double, double>> error_and_cost;
  std::istringstream lines(r.output);
  for (std::string line; std::getline(lines, line);) {
    std::istringstream words(line);
    std::vector<std::string> w{std::istream_iterator<std::string>(words), {}};
    if (w.size() >= 9 && (w[0] == "0.01" || w[0] == "0.0001")) error_and_cost[w[0]] = {std::stod(w[1]), std::stod(w[7])};
  }
  ASSERT_EQ(error_and_cost.size(), 2u) << r.output;
  EXPECT_LT(error_and_cost["0.0001"].first, error_and_cost["0.01"].first / 10) << r.output;
  EXPECT_GT(error_and_cost["0.0001"].second, error_and_cost["0.01"].second) << r.output;
  expect_bad_input("sweep " + file + " --march rayMarch --vary glsl.NOPE=1",
                   file + ": --vary glsl.NOPE: the shader has no #define NOPE and no uniform NOPE");
  expect_bad_input("sweep " + file + " --march rayMarch --vary max_steps=4",
                   "--vary max_steps=4: with --march, the axes are the shader's own (glsl.NAME)");
}

// The report renders a GLSL scene like any other (the main job's examples/shadertoy_map.glsl): its row, its image
// pair, its pass; and `all` still names every built-in beside it.
TEST_F(Cli, TheReportRendersAGlslSceneLikeAnyOther) {
  const std::string glsl = std::string(MARCHCHECK_EXAMPLES) + "/shadertoy_map.glsl";
  const CommandRun r = run("report --quick -o " + path("report") + " crum-torus " + glsl);
  ASSERT_EQ(r.status, 0) << r.output;
  const std::string html = contents("report/index.html");
  EXPECT_NE(html.find(">shadertoy_map</a>"), std::string::npos) << "its row in the scene table";
  bool image = false;
  for (const auto& entry : std::filesystem::directory_iterator(path("report/images")))
    image = image || entry.path().filename().string().starts_with("shadertoy_map");
  EXPECT_TRUE(image) << "its marched and reference images";
  EXPECT_EQ(run("validate " + glsl).status, 0) << "the example passes: the main job's report stays green";
}

// A driver that departs from IEEE float is seen as rays whose outcome differs from the CPU's: llvmpipe's dot() is
// not the sequential sum (it differs from x x + y y + z z in about a quarter of inputs), so a "marcher" that
// misses exactly where the two differ has rays with another outcome there, and none on the CPU. On another
// driver the count is only reported.
TEST_F(Cli, ADriverThatDepartsFromIeeeIsSeenAsRaysWithAnotherOutcome) {
  std::ofstream(path("dot.glsl")) << "#define MAX_DIST 50.0\nfloat map(vec3 p) { return length(p) - 1.0; }\n"
                                     "float probe(vec3 ro, vec3 rd) { vec3 v = rd * 3.7;\n"
                                     "  float s = v.x * v.x; s = s + v.y * v.y; s = s + v.z * v.z;\n"
                                     "  return dot(v, v) == s ? 1.0 : 2.0 * MAX_DIST; }\n";
  const CommandRun r = run("validate " + path("dot.glsl") + " --march probe");
  if (r.status == 2 && r.output.find("no GL driver") != std::string::npos) GTEST_SKIP() << r.output;
  const std::string said = "driver against CPU (the same marcher, float): ";
  const size_t at = r.output.find(said);
  ASSERT_NE(at, std::string::npos) << r.output;
  const int differs = std::atoi(r.output.c_str() + at + said.size());
  if (r.output.find("on llvmpipe") == std::string::npos) GTEST_SKIP() << "not llvmpipe: " << differs << " rays";
  EXPECT_GT(differs, 100) << r.output;  // of 2304 rays
}

TEST_F(Cli, ScenesExportAShadertoyShaderOrSayWhyNot) {
  const CommandRun r = run("scenes --export-glsl crum-torus");
  ASSERT_EQ(r.status, 0) << r.output;
  for (const char* part : {"void mainImage(out vec4 fragColor, in vec2 fragCoord)", "vec2 map(vec3 p)",
                           "float rayMarch(vec3 ro, vec3 rd)", "vec3 calcNormal(vec3 p)", "#define MAX_STEPS"})
    EXPECT_NE(r.output.find(part), std::string::npos) << part;
  std::ofstream(path("ball.glsl")) << "float map(vec3 p) { return length(p) - 1.0; }\n";
  expect_bad_input("scenes --export-glsl " + path("ball.glsl"),
                   "cannot export ball as GLSL: a GLSL field is exported by pasting its own source");
  expect_bad_input("scenes --export-glsl no-such-scene", "no-such-scene");
}

// The export's own marcher and normals, judged as a user's are: they pass, and the driver runs them as the CPU
// does, to the ulp. Broken variant: the exported marcher without its relaxed fallback (sdf-export-relaxed-no-fallback)
// overshoots.
TEST_F(Cli, AnExportedShadersOwnMarcherPassesAsAUsersWould) {
  std::string relaxed = run("scenes --export crum-torus").output;
  relaxed.replace(relaxed.find("\"sphere\""), 8, "\"relaxed\"");
  relaxed.replace(relaxed.find("\"relaxation\": 1.6"), 17, "\"relaxation\": 1.9");
  std::ofstream(path("relaxed.json")) << relaxed;
  for (const std::string& scene : {std::string("crum-torus"), path("relaxed.json")}) {
    std::ofstream(path("exported.glsl")) << run("scenes --export-glsl " + scene).output;
    const CommandRun r = run("validate " + path("exported.glsl") + " --march rayMarch --normal calcNormal");
    if (r.status == 2 && r.output.find("no GL driver") != std::string::npos) GTEST_SKIP() << r.output;
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("0 rays with another outcome, t within 0 ulps where both hit"), std::string::npos) << r.output;
  }
}

}  // namespace
