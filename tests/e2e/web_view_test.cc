// mbstream-viewer --web (issue 30) end to end: a real server, a real offscreen viewer under
// a private Xvfb serving its scene on 127.0.0.1:0, and Debian's chromium (headless, WebGL
// through SwiftShader) driven by playwright-core (web_page_check.mjs): the page draws the
// run, its probes (from its own scene graph) are where the server put the TCP, a second
// page shows the same run at once, a replay's controls and compare ghost work, and the page
// over HTTPS (--web-tls) with the server's tokens, a robot whose meshes are Collada, one
// with a textured OBJ and a missing mesh (drawn textured in the page and in the VTK window's
// snapshots, from the submitted bundle alone), and a published robot with textured Collada
// meshes (the Barrett WAM that Debian's dart-doc ships).
#include <gmock/gmock.h>
#include <signal.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGReader.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <random>
#include <set>

#include "tests/common/csv_rows.h"
#include "tests/common/server_process.h"
#include "tests/viewer/test_meshes.h"
#include "tests/viewer/xvfb_server.h"

namespace mbstream::testing {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::Not;
using ::testing::StartsWith;

// The fraction of a PNG's pixels that are strongly red, as web_page_check.mjs counts them in
// the page's screenshot (a test's red texture; no default colour is); -1 when unreadable.
double RedFractionOfPng(const fs::path& png) {
  vtkNew<vtkPNGReader> reader;
  if (!reader->CanReadFile(png.c_str())) return -1.0;
  reader->SetFileName(png.c_str());
  reader->Update();
  vtkImageData* image = reader->GetOutput();
  int dims[3];
  image->GetDimensions(dims);
  const int components = image->GetNumberOfScalarComponents();
  if (image->GetScalarType() != VTK_UNSIGNED_CHAR || components < 3) return -1.0;
  const auto* pixels = static_cast<const unsigned char*>(image->GetScalarPointer());
  const long count = static_cast<long>(dims[0]) * dims[1];
  long red = 0;
  for (long i = 0; i < count; ++i) {
    const unsigned char* p = pixels + i * components;
    if (p[0] > 60 && p[0] > 2 * p[1] && p[0] > 2 * p[2]) ++red;
  }
  return count > 0 ? static_cast<double>(red) / static_cast<double>(count) : -1.0;
}

// The last PNG the viewer wrote into `dir` (frame_NNNNN.png, in order).
fs::path LastSnapshot(const fs::path& dir) {
  fs::path last;
  std::error_code error;
  for (const auto& entry : fs::directory_iterator(dir, error)) {
    if (entry.path().extension() == ".png" && entry.path() > last) last = entry.path();
  }
  return last;
}

class WebViewTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("mbstream-web-" + std::to_string(std::random_device()()));
    fs::create_directories(dir_);
    server_ = std::make_unique<ServerProcess>(MBSTREAM_SERVER, (dir_ / "data").string());
    ASSERT_TRUE(xvfb_.Start()) << "Xvfb does not start (Debian package xvfb)";
  }
  void TearDown() override {
    const std::string group = ReadTextFile((dir_ / "viewer.pgid").string());
    if (!group.empty()) kill(-std::stoi(group), SIGTERM);
    server_.reset();
    fs::remove_all(dir_);
  }
  CommandOutcome Cli(const std::string& args) {
    return RunCommand(std::string(MBSTREAM_CLI) + " --server " + server_->address() + " " + args);
  }
  // Starts the viewer with --web 127.0.0.1:0 in a process group of its own; returns its URL.
  std::string StartViewer(const std::string& args) {
    const fs::path log = dir_ / "viewer.log";
    const std::string command = "DISPLAY=" + xvfb_.display() + " " + MBSTREAM_VIEWER +
                                " --server " + server_->address() +
                                " --offscreen --size 320x240 --web 127.0.0.1:0 " + args;
    EXPECT_EQ(
        RunCommand("setsid sh -c 'echo $$ > " + (dir_ / "viewer.pgid").string() + "; (" + command +
                   "; echo \"viewer exit $?\") > " + log.string() + " 2>&1' > /dev/null 2>&1 &")
            .exit_code,
        0);
    const std::optional<std::string> url = WaitForLineIn(log.string(), "web on ", 60);
    EXPECT_TRUE(url) << ReadTextFile(log.string());
    return url.value_or("");
  }
  // Restarts the server requiring tokens: an admin and a view token (in admin.token and
  // view.token of the test's folder) and the lines of `more_tokens`.
  void RestartServerWithTokens(const std::string& more_tokens) {
    std::ofstream(dir_ / "tokens") << "admin-token-0123456789 admin\n"
                                   << "view-token-0123456789 view\n"
                                   << more_tokens;
    std::ofstream(dir_ / "admin.token") << "admin-token-0123456789\n";
    std::ofstream(dir_ / "view.token") << "view-token-0123456789\n";
    server_ = std::make_unique<ServerProcess>(
        MBSTREAM_SERVER, (dir_ / "data-tokens").string(),
        std::vector<std::string>{"--token-file", (dir_ / "tokens").string()});
  }
  // Runs the browser on `url`; returns what it saw.
  nlohmann::json Browse(const std::string& url, const std::string& mode = "") {
    const CommandOutcome browsed = RunCommand(
        "node " MBSTREAM_SOURCE_DIR "/tests/e2e/web_page_check.mjs " + url + " " + dir_.string() +
        " " MBSTREAM_WEB_ROOT " " + mode + " 2>" + (dir_ / "browser.err").string());
    EXPECT_EQ(browsed.exit_code, 0)
        << browsed.output << ReadTextFile((dir_ / "browser.err").string())
        << ReadTextFile((dir_ / "viewer.log").string());
    nlohmann::json seen = nlohmann::json::parse(browsed.output, nullptr, false);
    EXPECT_TRUE(seen.is_object()) << browsed.output;
    if (!seen.is_object()) seen = {{"errors", {"the browser saw nothing"}}};
    // The lists the tests read, so that a failed browse fails their checks, not aborts them.
    for (const char* list : {"errors", "outside", "refused", "record"}) {
      if (!seen.contains(list)) seen[list] = nlohmann::json::array();
    }
    return seen;
  }
  // Follows a run of the submitted model `model` (at real time, 20 frames/s) with a viewer
  // started with `viewer_args` and the browser, cancels it, and checks what every submitted
  // model's page shows: the run, no error, the robot on the screenshot. The live runs here last
  // 600 s and are cancelled once the browser is done: a browser slowed by a busy machine must
  // not outlive the run (a 20 s run ended, and its viewer exited, before a loaded CI machine's
  // browser had opened its last page).
  nlohmann::json WatchSubmittedRun(const std::string& model, const std::string& viewer_args) {
    const std::string url = StartViewer("--follow --exit-after-runs 1 " + viewer_args);
    const CommandOutcome started =
        Cli("run " + model + " --duration 600 --output-interval 0.05 --realtime 1");
    EXPECT_EQ(started.exit_code, 0) << started.output;
    const std::string run = started.output.substr(0, started.output.find('\n'));
    const nlohmann::json seen = Browse(url);
    Cli("cancel " + run);
    PrintFigures(seen);
    const nlohmann::json errors = seen.value("errors", nlohmann::json());
    EXPECT_TRUE(errors.is_array()) << "the browser saw nothing";
    EXPECT_TRUE(errors.empty()) << errors;
    EXPECT_EQ(seen.value("run", ""), run);
    EXPECT_GT(seen.value("drawn_fraction", 0.0), 0.005) << "the screenshot shows no robot";
    return seen;
  }
  // Every recorded frame's first probe against the run's TCP at the same seq.
  void ExpectProbesAtTcp(const nlohmann::json& seen, const std::string& run_id) {
    ExpectProbesAtTcpWith(seen, run_id, "");
  }
  void ExpectProbesAtTcpWith(const nlohmann::json& seen, const std::string& run_id,
                             const std::string& cli_flags) {
    Cli(cli_flags + "result " + run_id + " --out " + (dir_ / "out").string());  // 1: cancelled
    const auto tcp = ReadCsv(dir_ / "out" / "tcp.csv");
    ASSERT_FALSE(tcp.empty());
    ASSERT_GE(seen["record"].size(), 10u);
    for (const auto& frame : seen["record"]) {
      const int64_t seq = frame["seq"].get<int64_t>();
      ASSERT_GE(seq, 0);
      ASSERT_LT(seq, static_cast<int64_t>(tcp.size()));
      ASSERT_FALSE(frame["probes"].empty());
      const auto& probe = frame["probes"][0];
      const auto& row = tcp[static_cast<size_t>(seq)];
      EXPECT_NEAR(probe["x"].get<double>(), std::stod(row[1]), 1e-5) << "seq " << seq;
      EXPECT_NEAR(probe["y"].get<double>(), std::stod(row[2]), 1e-5) << "seq " << seq;
      EXPECT_NEAR(probe["z"].get<double>(), std::stod(row[3]), 1e-5) << "seq " << seq;
    }
  }
  // Figures for docs/performance.md, in the test's log.
  static void PrintFigures(const nlohmann::json& seen) {
    std::vector<double> latency = seen.value("latency_ms", std::vector<double>{});
    std::sort(latency.begin(), latency.end());
    const auto at = [&](double q) {
      return latency.empty() ? -1.0 : latency[static_cast<size_t>(q * (latency.size() - 1))];
    };
    std::printf(
        "web figures: page load %d ms, first frame %d ms, late join %d ms, page bytes %lld, "
        "scene bytes %lld, frame bytes %lld, triangles %lld, frames %lld missed %lld, latency "
        "p50 %.1f ms p99 %.1f ms (%zu frames), drawn %.3f\n",
        seen.value("load_ms", -1), seen.value("first_frame_ms", -1), seen.value("late_join_ms", -1),
        seen.value("page_bytes", -1LL), seen.value("scene_bytes", -1LL),
        seen.value("frame_bytes", -1LL), seen.value("triangles", -1LL), seen.value("frames", -1LL),
        seen.value("missed", -1LL), at(0.5), at(0.99), latency.size(),
        seen.value("drawn_fraction", -1.0));
  }

  fs::path dir_;
  std::unique_ptr<ServerProcess> server_;
  viewer::testing::XvfbServer xvfb_;
};

TEST_F(WebViewTest, PageDrawsTheLiveSeedRunWithTheTcpWhereTheServerPutsIt) {
  const std::string url = StartViewer("--follow --exit-after-runs 1");
  ASSERT_THAT(url, StartsWith("http://127.0.0.1:"));
  const CommandOutcome started =
      Cli("run irb1600 --spec models/irb1600/seed-run.json --duration 600 --realtime 1");
  ASSERT_EQ(started.exit_code, 0) << started.output;
  const std::string run = started.output.substr(0, started.output.find('\n'));
  const nlohmann::json seen = Browse(url);
  Cli("cancel " + run);
  PrintFigures(seen);
  EXPECT_EQ(seen.value("run", ""), run);
  EXPECT_EQ(seen.value("second_run", ""), run);  // the late joiner: the same run at once
  EXPECT_EQ(seen.value("state", ""), "running");
  EXPECT_TRUE(seen["errors"].empty()) << seen["errors"];
  EXPECT_TRUE(seen["outside"].empty()) << seen["outside"];  // nothing from another host
  EXPECT_GT(seen.value("drawn_fraction", 0.0), 0.01) << "the screenshot shows no robot";
  EXPECT_THAT(seen.value("hud", ""), HasSubstr("run " + run + "  running"));
  EXPECT_TRUE(fs::file_size(dir_ / "web_page.png") > 1000);
  ExpectProbesAtTcp(seen, seen.value("run", ""));
  ASSERT_TRUE(WaitForLineIn((dir_ / "viewer.log").string(), "viewer exit ", 60));
}

TEST_F(WebViewTest, ReplayControlsAndTheCompareGhostWorkFromThePage) {
  const std::string spec = " --spec models/irb1600/seed-run.json --realtime 50 --watch";
  const CommandOutcome a = Cli("run irb1600" + spec);
  ASSERT_EQ(a.exit_code, 0) << a.output;
  const CommandOutcome b = Cli("run irb1600" + spec);
  ASSERT_EQ(b.exit_code, 0) << b.output;
  const std::string run_a = a.output.substr(0, a.output.find('\n'));
  const std::string run_b = b.output.substr(0, b.output.find('\n'));
  const std::string url = StartViewer("--run " + run_a + " --compare " + run_b + " --loop");
  const nlohmann::json seen = Browse(url, "replay");
  PrintFigures(seen);
  ASSERT_TRUE(seen.contains("replay")) << seen.dump();
  EXPECT_EQ(seen["replay"]["after_seek"], 100);
  EXPECT_EQ(seen["replay"]["compare"], run_b);
  EXPECT_NEAR(seen["replay"]["ghost_distance"].get<double>(), 0.0, 1e-9);  // the same motion
  EXPECT_THAT(seen.value("hud", ""), HasSubstr("ghost " + run_b));
  // The page's speed control: the viewer's frames report the speed the page chose (x5, then
  // x1). The paces measured in wall time are figures, not assertions (a loaded machine slows
  // the page's clock, not the replay's law): they are printed for the log.
  ASSERT_TRUE(seen["replay"].contains("speed")) << seen["replay"];
  const double fast = seen["replay"]["speed"]["fast"].get<double>();
  const double slow = seen["replay"]["speed"]["slow"].get<double>();
  std::printf("replay pace from the page: x5 gives %.2f, x1 gives %.2f run s per wall s\n", fast,
              slow);
  EXPECT_EQ(seen["replay"]["speed"]["reported"], nlohmann::json::array({5, 1}));
  EXPECT_GT(fast, 0.0);
  EXPECT_GT(slow, 0.0);
  EXPECT_TRUE(seen["errors"].empty()) << seen["errors"];
  EXPECT_GT(seen.value("drawn_fraction", 0.0), 0.01);
  ExpectProbesAtTcp(seen, run_a);
}

// A real page stalled (issue 42, item 8): a second browser's page is stopped whole (SIGSTOP
// of its browser's processes, as a laptop's lid closed) while the first page gets 1000 frames
// (10 s of the live seed run at 100 frames/s), then woken. The viewer kept only the newest frame
// for it: its HUD's missed count rises. The first page got every frame the viewer posted meanwhile,
// and the viewer's probe reports reached the server for every frame of the stall.
TEST_F(WebViewTest, AStalledPageMissesFramesWhileTheOtherKeepsPaceAndProbesGoOn) {
  const std::string url = StartViewer("--follow --exit-after-runs 1");
  const CommandOutcome started =
      Cli("run irb1600 --spec models/irb1600/seed-run.json --duration 600 --output-interval 0.01 "
          "--realtime 1");
  ASSERT_EQ(started.exit_code, 0) << started.output;
  const std::string run = started.output.substr(0, started.output.find('\n'));
  const nlohmann::json seen = Browse(url, "stall:1000");
  Cli("cancel " + run);
  ASSERT_TRUE(seen.contains("stall")) << seen.dump().substr(0, 2000);
  const nlohmann::json& stall = seen["stall"];
  const auto figure = [&](const char* page, const char* what) {
    return stall[page][what].get<int64_t>();
  };
  std::printf(
      "stall: the stalled page missed %lld frames; the other got %lld while the viewer drew %lld "
      "(missed %lld), seq %lld to %lld\n",
      static_cast<long long>(figure("stalled_after", "missed") -
                             figure("stalled_before", "missed")),
      static_cast<long long>(figure("after", "frames") - figure("before", "frames")),
      static_cast<long long>(figure("after", "viewer_frames") - figure("before", "viewer_frames")),
      static_cast<long long>(figure("after", "missed") - figure("before", "missed")),
      static_cast<long long>(figure("before", "seq")),
      static_cast<long long>(figure("after", "seq")));
  EXPECT_GT(figure("stalled_after", "missed"), figure("stalled_before", "missed"));
  EXPECT_THAT(stall.value("stalled_hud", ""), HasSubstr("(missed "));
  // The other page kept pace: every frame message the viewer published reached it (none
  // missed: the web thread may merge poses when it falls behind the viewer, which the viewer's
  // own frame count shows), and its seq followed the viewer's frames.
  const int64_t got = figure("after", "frames") - figure("before", "frames");
  const int64_t drawn = figure("after", "viewer_frames") - figure("before", "viewer_frames");
  EXPECT_GE(got, 1000);
  EXPECT_LE(figure("after", "missed") - figure("before", "missed"), got / 50 + 1);
  EXPECT_GE(static_cast<double>(figure("after", "seq") - figure("before", "seq")),
            0.95 * static_cast<double>(drawn));
  // The probe reports kept arriving: one stored for (nearly) every seq of the stall.
  Cli("result " + run + " --out " + (dir_ / "out").string());  // exit 1: cancelled
  const auto probes = ReadCsv(dir_ / "out" / "probes.csv");
  std::set<int64_t> reported_seqs;  // a report per probe and frame
  for (const auto& row : probes) {
    const int64_t seq = std::stoll(row[0]);
    if (seq > figure("before", "seq") && seq <= figure("after", "seq")) reported_seqs.insert(seq);
  }
  const auto reported = static_cast<int64_t>(reported_seqs.size());
  const int64_t frames = figure("after", "seq") - figure("before", "seq");
  EXPECT_GE(static_cast<double>(reported), 0.95 * static_cast<double>(frames))
      << reported << " probe reports for " << frames << " frames of the stall";
  ASSERT_TRUE(WaitForLineIn((dir_ / "viewer.log").string(), "viewer exit ", 60));
}

// --web-tls and tokens: a server that requires tokens, the viewer's page over HTTPS (a
// self-signed certificate made by openssl), a page with a view token in its URL fragment draws
// the run; pages with a token lacking the view role, or none, get nothing but the refusal.
TEST_F(WebViewTest, HttpsPageWithAViewTokenDrawsTheRunAndOthersAreRefused) {
  const std::string d = dir_.string();
  const CommandOutcome made = RunCommand(
      "openssl req -x509 -newkey rsa:2048 -nodes -days 2 -subj /CN=127.0.0.1 -addext "
      "subjectAltName=IP:127.0.0.1 -keyout " +
      d + "/web.key -out " + d + "/web.pem 2>&1");
  ASSERT_EQ(made.exit_code, 0) << made.output;
  RestartServerWithTokens("not-a-viewer-token submit\n");
  const std::string url = StartViewer("--follow --exit-after-runs 1 --token-file " + d +
                                      "/view.token --web-tls " + d + "/web.pem," + d + "/web.key");
  ASSERT_THAT(url, StartsWith("https://127.0.0.1:"));
  const std::string admin = " --token-file " + d + "/admin.token ";
  const CommandOutcome started =
      Cli(admin + "run irb1600 --spec models/irb1600/seed-run.json --duration 600 --realtime 1");
  ASSERT_EQ(started.exit_code, 0) << started.output;
  const std::string run = started.output.substr(0, started.output.find('\n'));
  const nlohmann::json seen = Browse(url + "#token=view-token-0123456789", "denied");
  Cli(admin + "cancel " + run);
  PrintFigures(seen);
  EXPECT_EQ(seen.value("run", ""), run);
  EXPECT_EQ(seen.value("protocol", ""), "https:");
  EXPECT_EQ(seen.value("hash_after_load", "?"), "");  // the token is off the address bar
  EXPECT_TRUE(seen["errors"].empty()) << seen["errors"];
  EXPECT_TRUE(seen["outside"].empty()) << seen["outside"];
  ASSERT_EQ(seen["refused"].size(), 2u) << seen.dump();
  EXPECT_EQ(seen["refused"][0]["status"], 403) << seen["refused"][0];  // no view role
  EXPECT_EQ(seen["refused"][1]["status"], 401) << seen["refused"][1];  // no token
  for (const auto& refused : seen["refused"]) {
    EXPECT_EQ(refused["scene"], 0) << refused;  // nothing of the run reached it
    EXPECT_EQ(refused["frames"], 0) << refused;
    EXPECT_EQ(refused["form"], true) << refused;  // it asks for a token
  }
  ExpectProbesAtTcpWith(seen, run, admin);
  const std::string log = ReadTextFile((dir_ / "viewer.log").string());
  EXPECT_THAT(log, HasSubstr("refused (403)"));
  EXPECT_THAT(log, ::testing::Not(HasSubstr("view-token-0123456789")));  // never logged
  ASSERT_TRUE(WaitForLineIn((dir_ / "viewer.log").string(), "viewer exit ", 60));
}

// A replay is one for the viewer's window and every page: a page whose token has only the view
// role watches it (its controls disabled, a control it sends anyway refused by the viewer), a
// page whose token has the run role (as ReplayRun needs) pauses it for every page.
TEST_F(WebViewTest, AViewOnlyPageCannotSteerTheSharedReplayARunTokenCan) {
  const std::string d = dir_.string();
  RestartServerWithTokens("steer-token-0123456789 view,run\n");
  const std::string admin = " --token-file " + d + "/admin.token ";
  const CommandOutcome a =
      Cli(admin + "run irb1600 --spec models/irb1600/seed-run.json --realtime 50 --watch");
  ASSERT_EQ(a.exit_code, 0) << a.output;
  const std::string run = a.output.substr(0, a.output.find('\n'));
  // The viewer's own token has the view role only: it does not lend pages more.
  const std::string url = StartViewer("--run " + run + " --loop --token-file " + d + "/view.token");
  const nlohmann::json seen =
      Browse(url + "#token=view-token-0123456789", "watch-only:steer-token-0123456789");
  ASSERT_TRUE(seen.contains("watch_only")) << seen.dump().substr(0, 2000);
  const nlohmann::json& watch = seen["watch_only"];
  EXPECT_EQ(watch["controls"], false) << watch;
  EXPECT_EQ(watch["disabled"], true) << watch;
  EXPECT_EQ(watch["paused_after"], false) << watch;  // its pause did nothing
  EXPECT_THAT(watch.value("message", ""), HasSubstr("run role"));
  EXPECT_EQ(watch["steer_controls"], true) << watch;
  EXPECT_EQ(watch["paused_for_both"], true) << watch;
  EXPECT_THAT(seen.value("hud", ""), HasSubstr("watching only"));
  EXPECT_TRUE(seen["errors"].empty()) << seen["errors"];
  EXPECT_THAT(ReadTextFile((dir_ / "viewer.log").string()), HasSubstr("control refused"));
}

// A robot whose every visual is a Collada mesh, as published ROS descriptions ship them (the
// meshes written by the test: no third-party files), submitted with its meshes and run: the
// page draws the viewer's triangles of each mesh in its Collada material's colour.
// A world (docs/worlds.md): the IRB 1600 included, a static table and three free boxes. The
// page draws every model's links (a part per visual on at least twelve frames: the robot's
// seven, the table's two, the boxes' three) from a run whose frames carry the boxes' seven
// coordinates each, and its probe is where the server put the robot's TCP.
TEST_F(WebViewTest, AWorldsModelsAreAllDrawnAndItsTcpProbedFromThePage) {
  const CommandOutcome submitted =
      Cli("submit " MBSTREAM_SOURCE_DIR "/models/worlds/irb1600_table --name irb1600_table");
  ASSERT_EQ(submitted.exit_code, 0) << submitted.output;
  const nlohmann::json seen = WatchSubmittedRun("irb1600_table", "");
  ASSERT_TRUE(seen.contains("parts") && seen["parts"].is_array()) << seen.dump().substr(0, 2000);
  std::set<int> frames;
  for (const auto& part : seen["parts"]) frames.insert(part["frame"].get<int>());
  EXPECT_GE(frames.size(), 12u) << seen["parts"];
  ExpectProbesAtTcp(seen, seen.value("run", ""));
  ASSERT_TRUE(WaitForLineIn((dir_ / "viewer.log").string(), "viewer exit ", 60));
}

// A world whose included models are drawn from their mesh files (issue 43, docs/worlds.md,
// "Meshes of included models"): tests/data/worlds/mesh_world/ submitted as a folder (its
// STL, OBJ and Collada files attached from the models' folders, named relative to their
// model.sdf or by model://) reaches the page with every mesh: the post's column and arm (12
// triangles each, red), the crate's two cubes (24, green), the shelf's block (12, its
// Collada file's blue); none is a placeholder.
TEST_F(WebViewTest, AWorldsIncludedModelsAreDrawnFromTheirMeshFiles) {
  const CommandOutcome submitted =
      Cli("submit " MBSTREAM_SOURCE_DIR "/tests/data/worlds/mesh_world --name mesh_world");
  ASSERT_EQ(submitted.exit_code, 0) << submitted.output;
  EXPECT_THAT(submitted.output, Not(HasSubstr("not found"))) << submitted.output;
  const nlohmann::json seen = WatchSubmittedRun("mesh_world", "");
  ASSERT_TRUE(seen.contains("parts") && seen["parts"].is_array()) << seen.dump().substr(0, 2000);
  EXPECT_EQ(seen.value("triangles", 0), 12 + 12 + 24 + 12) << seen["parts"];
  std::multiset<std::string> colours;
  for (const auto& part : seen["parts"]) {
    const double r = part["color"][0].get<double>(), g = part["color"][1].get<double>(),
                 b = part["color"][2].get<double>();
    colours.insert(r > g + 0.5 && r > b + 0.5   ? "red"
                   : g > r + 0.5 && g > b + 0.5 ? "green"
                   : b > r + 0.5 && b > g + 0.5 ? "blue"
                                                : "other");
    EXPECT_EQ(part["opacity"].get<double>(), 1.0) << part << " (a placeholder is translucent)";
  }
  EXPECT_EQ(colours, (std::multiset<std::string>{"red", "red", "green", "blue"})) << seen["parts"];
  EXPECT_THAT(seen.value("hud", ""), Not(HasSubstr("missing")));
  ASSERT_TRUE(WaitForLineIn((dir_ / "viewer.log").string(), "viewer exit ", 60));
}

// Contacts on the page (issue 44): with --contacts the viewer sends each frame's contacts to
// the pages, which draw a point and a force arrow each. A box resting on a plane: four
// corners, each arrow the floor's share of the weight, pointing down.
TEST_F(WebViewTest, APageDrawsTheContactsOfABoxRestingOnAPlane) {
  const CommandOutcome submitted =
      Cli("submit " MBSTREAM_SOURCE_DIR "/tests/data/contact/box_resting.sdf --name box");
  ASSERT_EQ(submitted.exit_code, 0) << submitted.output;
  const nlohmann::json seen = WatchSubmittedRun("box", "--contacts");
  ASSERT_GE(seen["record"].size(), 10u);
  for (const auto& frame : seen["record"]) {
    if (frame["seq"].get<int64_t>() == 0) continue;  // at t = 0 the box just touches
    ASSERT_EQ(frame["contacts"].size(), 4u) << frame.dump();
    for (const auto& c : frame["contacts"]) {
      EXPECT_NEAR(std::abs(c["point"]["x"].get<double>()), 0.1, 1e-6) << c.dump();
      EXPECT_NEAR(std::abs(c["point"]["y"].get<double>()), 0.1, 1e-6) << c.dump();
      // Downwards, and no longer than the largest force so far's 0.25 m (the box settles,
      // so its first frames' forces are larger than its weight's share).
      const double drop = c["point"]["z"].get<double>() - c["tip"]["z"].get<double>();
      EXPECT_GT(drop, 0.05) << c.dump();
      EXPECT_LE(drop, 0.25 + 1e-9) << c.dump();
    }
  }
  ASSERT_TRUE(WaitForLineIn((dir_ / "viewer.log").string(), "viewer exit ", 60));
}

TEST_F(WebViewTest, AColladaMeshedRobotIsDrawnWithItsMaterialColours) {
  const fs::path robot = dir_ / "colladabot";
  fs::create_directories(robot / "meshes");
  using Eigen::Vector3d;
  const Vector3d blue(0.2, 0.4, 0.8), red(0.9, 0.1, 0.1), green(0.1, 0.8, 0.2);
  viewer::testing::WriteColladaBox(robot / "meshes/base.dae", Vector3d(-150, -150, 0),
                                   Vector3d(150, 150, 200), 0.001, "Z_UP", blue);  // mm
  viewer::testing::WriteColladaBox(robot / "meshes/arm.dae", Vector3d(-0.05, -0.05, 0),
                                   Vector3d(0.05, 0.05, 0.5), 1.0, "Z_UP", red);
  viewer::testing::WriteColladaBox(robot / "meshes/tool.dae", Vector3d(-0.02, -0.02, 0),
                                   Vector3d(0.02, 0.02, 0.1), 1.0, "Z_UP", green);
  const auto link = [](const std::string& name, const std::string& mesh) {
    return "<link name=\"" + name + "\"><inertial><mass value=\"1\"/><inertia ixx=\"0.01\" " +
           "iyy=\"0.01\" izz=\"0.01\" ixy=\"0\" ixz=\"0\" iyz=\"0\"/></inertial>" +
           (mesh.empty() ? ""
                         : "<visual><geometry><mesh filename=\"meshes/" + mesh +
                               "\"/></geometry></visual>") +
           "</link>\n";
  };
  const auto joint = [](const std::string& name, const std::string& type, const std::string& parent,
                        const std::string& child, const std::string& xyz) {
    return "<joint name=\"" + name + "\" type=\"" + type + "\"><parent link=\"" + parent +
           "\"/><child link=\"" + child + "\"/><origin xyz=\"" + xyz +
           "\"/><axis xyz=\"0 1 0\"/><limit lower=\"-3\" upper=\"3\" effort=\"100\" " +
           "velocity=\"5\"/></joint>\n";
  };
  std::ofstream(robot / "colladabot.urdf")
      << "<robot name=\"colladabot\">\n"
      << link("base_link", "base.dae") << link("arm", "arm.dae") << link("tool", "tool.dae")
      << link("tcp", "") << joint("j1", "revolute", "base_link", "arm", "0 0 0.2")
      << joint("j2", "revolute", "arm", "tool", "0 0 0.5")
      << joint("tool_tcp", "fixed", "tool", "tcp", "0 0 0.1") << "</robot>\n";
  const CommandOutcome submitted = Cli("submit " + (robot / "colladabot.urdf").string());
  ASSERT_EQ(submitted.exit_code, 0) << submitted.output;
  const nlohmann::json seen = WatchSubmittedRun("colladabot", "");
  EXPECT_EQ(seen.value("triangles", 0), 36) << "three Collada boxes of 12 triangles";
  ASSERT_TRUE(seen["parts"].is_array()) << seen.dump().substr(0, 2000);
  std::vector<Vector3d> colours;
  for (const auto& part : seen["parts"]) {
    colours.emplace_back(part["color"][0].get<double>(), part["color"][1].get<double>(),
                         part["color"][2].get<double>());
  }
  for (const Vector3d& expected : {blue, red, green}) {
    EXPECT_TRUE(std::any_of(colours.begin(), colours.end(),
                            [&](const Vector3d& c) { return (c - expected).norm() < 0.02; }))
        << "no part in " << expected.transpose() << ": " << seen["parts"];
  }
  ASSERT_TRUE(WaitForLineIn((dir_ / "viewer.log").string(), "viewer exit ", 60));
}

// A robot as published humanoids ship them: an OBJ whose colour is a texture (a black Kd and
// map_Kd) and a link whose mesh is missing.
// The page draws the texture (the viewer sends its image and coordinates) and the missing
// mesh's tinted box, and names the missing mesh on one HUD line.
TEST_F(WebViewTest, ATexturedMeshAndAMissingOneLookInThePageAsInTheWindow) {
  const fs::path robot = dir_ / "skinbot";
  fs::create_directories(robot);
  {  // a 16 x 16 BMP (24-bit, rows bottom up) of one colour
    std::ofstream bmp(robot / "skin.bmp", std::ios::binary);
    const auto u32 = [&](std::uint32_t v) {
      for (int k = 0; k < 4; ++k) bmp.put(static_cast<char>((v >> (8 * k)) & 0xff));
    };
    const auto u16 = [&](std::uint16_t v) {
      bmp.put(static_cast<char>(v & 0xff));
      bmp.put(static_cast<char>(v >> 8));
    };
    bmp << "BM";
    u32(54 + 16 * 16 * 3);
    u32(0);
    u32(54);
    u32(40);
    u32(16);
    u32(16);
    u16(1);
    u16(24);
    u32(0);
    u32(16 * 16 * 3);
    u32(2835);
    u32(2835);
    u32(0);
    u32(0);
    for (int i = 0; i < 16 * 16; ++i) bmp << '\x28' << '\x3c' << '\xc8';  // B G R: 200, 60, 40
  }
  std::ofstream(robot / "cube.mtl") << "newmtl skin\nKd 0 0 0\nmap_Kd skin.bmp\n";
  {
    std::ofstream obj(robot / "cube.obj");
    obj << "mtllib cube.mtl\nusemtl skin\n";
    for (int i = 0; i < 8; ++i) {
      obj << "v " << ((i & 1) ? 0.1 : -0.1) << ' ' << ((i & 2) ? 0.1 : -0.1) << ' '
          << ((i & 4) ? 0.2 : 0.0) << "\n";
    }
    obj << "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n";
    const int faces[6][4] = {{1, 3, 4, 2}, {5, 6, 8, 7}, {1, 2, 6, 5},
                             {3, 7, 8, 4}, {1, 5, 7, 3}, {2, 4, 8, 6}};
    for (const auto& face : faces) {
      obj << "f";
      for (int k = 0; k < 4; ++k) obj << ' ' << face[k] << '/' << (k + 1);
      obj << "\n";
    }
  }
  const std::string inertial =
      "<inertial><mass value=\"1\"/><inertia ixx=\"0.01\" iyy=\"0.01\" izz=\"0.01\" ixy=\"0\" "
      "ixz=\"0\" iyz=\"0\"/></inertial>";
  std::ofstream(robot / "skinbot.urdf")
      << "<robot name=\"skinbot\">\n<link name=\"base_link\">" << inertial
      << "<visual><geometry><mesh filename=\"cube.obj\"/></geometry></visual></link>\n"
      << "<link name=\"arm\">" << inertial
      << "<visual><geometry><mesh filename=\"meshes/gone.dae\"/></geometry></visual></link>\n"
      << "<link name=\"tcp\"/>\n"
      << "<joint name=\"j1\" type=\"revolute\"><parent link=\"base_link\"/><child link=\"arm\"/>"
      << "<origin xyz=\"0 0 0.2\"/><axis xyz=\"0 1 0\"/><limit lower=\"-3\" upper=\"3\" "
      << "effort=\"100\" velocity=\"5\"/></joint>\n"
      << "<joint name=\"arm_tcp\" type=\"fixed\"><parent link=\"arm\"/><child link=\"tcp\"/>"
      << "<origin xyz=\"0 0 0.3\"/></joint>\n</robot>\n";
  const CommandOutcome submitted = Cli("submit " + (robot / "skinbot.urdf").string());
  ASSERT_EQ(submitted.exit_code, 0) << submitted.output;
  // The bundle carries the OBJ's .mtl and its image (mbstream submit attaches them, the
  // server keeps them): the viewer draws the texture from the server's bundle alone.
  EXPECT_THAT(submitted.output, HasSubstr(", 3 assets"));
  // The VTK window writes a snapshot every 10th draw: the same texture there.
  const nlohmann::json seen =
      WatchSubmittedRun("skinbot", "--snapshot-every 10 --snapshots " + (dir_ / "window").string());
  EXPECT_THAT(seen.value("hud", ""), HasSubstr("1 mesh missing: gone.dae"));
  std::printf("web look: drawn %.4f, red %.4f of the page\n", seen.value("drawn_fraction", 0.0),
              seen.value("red_fraction", 0.0));
  // The cube's red texture on the screen (the placeholder's orange is not that red).
  EXPECT_GT(seen.value("red_fraction", 0.0), 0.002) << "the page draws no texture";
  ASSERT_TRUE(seen["parts"].is_array()) << seen.dump().substr(0, 2000);
  int textured = 0, tinted = 0;
  for (const auto& part : seen["parts"]) {
    textured += part.value("textured", false) ? 1 : 0;
    tinted += part.value("opacity", 1.0) < 1.0 ? 1 : 0;
  }
  EXPECT_EQ(textured, 1) << seen["parts"] << ReadTextFile((dir_ / "viewer.log").string());
  EXPECT_EQ(tinted, 1) << seen["parts"];
  ASSERT_TRUE(WaitForLineIn((dir_ / "viewer.log").string(), "viewer exit ", 60));
  const fs::path window = LastSnapshot(dir_ / "window");  // complete: the viewer has exited
  ASSERT_FALSE(window.empty()) << "the VTK window wrote no snapshot";
  const double window_red = RedFractionOfPng(window);
  std::printf("window look: red %.4f of %s\n", window_red, window.filename().c_str());
  EXPECT_GT(window_red, 0.002) << "the VTK window draws no texture (" << window << ")";
}

// A published robot whose meshes are textured Collada: the Barrett WAM of DART's examples
// (Debian's dart-doc: wam.urdf, meshes/wam/*.dae naming ../images/*.jpg, package:// URIs).
// Submitted as published, with nothing but its folder; the page draws every mesh, six of them
// with their images, and names no missing mesh.
TEST_F(WebViewTest, APublishedTexturedColladaRobotIsDrawnFromItsSubmittedBundle) {
  const fs::path published = "/usr/share/doc/dart/data/urdf/wam";
  if (!fs::exists(published / "wam.urdf")) {
    GTEST_SKIP() << published << " is not here: install Debian's dart-doc (scripts/setup.sh)";
  }
  fs::copy(published, dir_ / "wam", fs::copy_options::recursive);
  const CommandOutcome submitted = Cli("submit " + (dir_ / "wam" / "wam.urdf").string());
  ASSERT_EQ(submitted.exit_code, 0) << submitted.output;
  EXPECT_THAT(submitted.output, HasSubstr(", 14 assets")) << "8 Collada meshes and 6 images";
  const nlohmann::json seen = WatchSubmittedRun("wam", "");
  EXPECT_GT(seen.value("triangles", 0), 5000) << "the WAM's Collada meshes (9,433 drawn)";
  EXPECT_THAT(seen.value("hud", ""), Not(HasSubstr("missing")));
  ASSERT_TRUE(seen["parts"].is_array()) << seen.dump().substr(0, 2000);
  int textured = 0;
  for (const auto& part : seen["parts"]) textured += part.value("textured", false) ? 1 : 0;
  EXPECT_GE(textured, 6) << seen["parts"] << ReadTextFile((dir_ / "viewer.log").string());
  ASSERT_TRUE(WaitForLineIn((dir_ / "viewer.log").string(), "viewer exit ", 60));
}

}  // namespace
}  // namespace mbstream::testing
