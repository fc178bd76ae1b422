// The accuracy report as a user meets it: a folder that opens in a browser with every image, written atomically,
// with scene text escaped.
#include "command_run.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <utility>

namespace {

namespace fs = std::filesystem;

std::string read(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

size_t count(const std::string& text, const std::string& what) {
  size_t n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

class Report : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("marchcheck_report_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

struct BrowserView {
  std::string images_loaded;  // "loaded/total" as the page's own check reports it
  std::string console;        // console messages the page logged
};

// Loads the page in headless Chromium (Debian's package) and reads what the page's script reports.
BrowserView open_in_chromium(const fs::path& page, const fs::path& scratch) {
  const CommandRun r = run_shell("chromium --headless --no-sandbox --disable-gpu --user-data-dir=" +
                                 (scratch / "profile").string() + " --enable-logging=stderr --v=0 " +
                                 "--virtual-time-budget=10000 --dump-dom file://" + fs::absolute(page).string());
  BrowserView view;
  const std::string marker = "data-images-loaded=\"";
  if (const size_t at = r.output.find(marker); at != std::string::npos) {
    const size_t begin = at + marker.size();
    view.images_loaded = r.output.substr(begin, r.output.find('"', begin) - begin);
  }
  std::istringstream lines(r.output);  // the DOM on stdout, Chromium's log (console messages among it) on stderr
  for (std::string line; std::getline(lines, line);)
    if (line.find(":CONSOLE") != std::string::npos) view.console += line + "\n";
  return view;
}

TEST_F(Report, OpensInChromiumWithEveryImageAndPlotAndNoConsoleError) {
  if (run_shell("command -v chromium").status != 0) GTEST_SKIP() << "chromium is not installed (scripts/setup.sh installs it)";
  const fs::path out = dir_ / "report";
  const CommandRun r = run("report --quick -o " + out.string() + " crum-torus fogerty-defect-steps");
  ASSERT_EQ(r.status, 0) << r.output;  // the correct scene passes and the defect is caught
  const std::string html = read(out / "index.html");
  EXPECT_NE(html.find("fogerty-defect-steps"), std::string::npos);
  EXPECT_NE(html.find("hit.undecided"), std::string::npos);  // the check that catches the defect
  const size_t images = count(html, "<img ");
  EXPECT_EQ(images, 2u * 5 + 5);  // marched, reference, error, steps, slice per scene; five plots
  const BrowserView view = open_in_chromium(out / "index.html", dir_);
  EXPECT_EQ(view.images_loaded, std::to_string(images) + "/" + std::to_string(images));
  EXPECT_EQ(view.console, "");

  // Broken variant: a report missing one plot (grazing.png deleted); the page counts it and logs a console error.
  fs::remove(out / "plots" / "grazing.png");
  const BrowserView broken = open_in_chromium(out / "index.html", dir_);
  EXPECT_EQ(broken.images_loaded, std::to_string(images - 1) + "/" + std::to_string(images));
  EXPECT_NE(broken.console, "");
}

TEST_F(Report, AFailedRunLeavesThePreviousReportWholeAndNoTemporaryFolder) {
  const fs::path out = dir_ / "report";
  ASSERT_EQ(run("report --quick -o " + out.string() + " crum-torus").status, 0);
  const std::string before = read(out / "index.html");
  // The plots fail at the very end, after every image and table of the new report was written.
  const CommandRun failed = run_shell("MARCHCHECK_PYTHON=/bin/false " + std::string(MARCHCHECK_BINARY) + " report --quick -o " +
                                      out.string() + " crum-smooth");
  EXPECT_EQ(failed.status, 2) << failed.output;
  EXPECT_NE(failed.output.find("plots: /bin/false"), std::string::npos) << failed.output;
  EXPECT_NE(failed.output.find("previous report"), std::string::npos) << failed.output;
  EXPECT_EQ(read(out / "index.html"), before);
  EXPECT_TRUE(fs::exists(out / "images" / "crum-torus.marched.png"));
  EXPECT_FALSE(fs::exists(out / "images" / "crum-smooth.marched.png"));
  for (const auto& entry : fs::directory_iterator(dir_))
    EXPECT_EQ(entry.path().filename().string().find(".tmp"), std::string::npos) << entry.path();
  // A successful run replaces it whole.
  ASSERT_EQ(run("report --quick -o " + out.string() + " crum-smooth").status, 0);
  EXPECT_FALSE(fs::exists(out / "images" / "crum-torus.marched.png"));
  EXPECT_TRUE(fs::exists(out / "images" / "crum-smooth.marched.png"));
}

// The report's exit status is the gate: 1 when a correct scene fails a check or a defect variant passes every
// check (uncaught), though the report is written either way. Broken variants: an uncaught defect counted as
// expected, a failing correct scene counted as expected.
TEST_F(Report, ExitsOneWhenACorrectSceneFailsOrADefectGoesUncaught) {
  ASSERT_EQ(run_shell(std::string(MARCHCHECK_BINARY) + " scenes --export crum-torus > " + (dir_ / "t.json").string()).status, 0);
  const std::string exported = read(dir_ / "t.json");
  ASSERT_NE(exported.find("\"limits\": {}"), std::string::npos);
  // A limit no march can meet: the rays' norm error is ~2e-16, never below 0.
  std::string failing = exported;
  failing.replace(failing.find("\"limits\": {}"), 12, "\"limits\": {\"camera.ray_norm_err\": 0}");
  std::ofstream(dir_ / "failing.json") << failing;
  // Declared a defect variant, yet it passes every check.
  std::string uncaught = exported;
  uncaught.replace(0, 1, "{\"defects\": [\"none really\"], ");
  std::ofstream(dir_ / "uncaught.json") << uncaught;
  for (const auto& [file, status] : {std::pair{"t.json", 0}, std::pair{"failing.json", 1}, std::pair{"uncaught.json", 1}}) {
    const CommandRun r = run("report --quick -o " + (dir_ / "out").string() + " " + (dir_ / file).string());
    EXPECT_EQ(r.status, status) << file << ": " << r.output;
    EXPECT_TRUE(fs::exists(dir_ / "out" / "index.html")) << file;
  }
}

TEST_F(Report, RefusesToReplaceAFolderThatIsNotAReport) {
  const fs::path out = dir_ / "notes";
  fs::create_directories(out);
  std::ofstream(out / "todo.txt") << "mine";
  const CommandRun r = run("report --quick -o " + out.string() + " crum-torus");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("not a marchcheck report"), std::string::npos) << r.output;
  EXPECT_EQ(read(out / "todo.txt"), "mine");
}

TEST_F(Report, SceneTextIsEscaped) {
  ASSERT_EQ(run_shell(std::string(MARCHCHECK_BINARY) + " scenes --export crum-torus > " + (dir_ / "t.json").string()).status, 0);
  std::string scene = read(dir_ / "t.json");
  const std::string key = "\"description\": \"";
  const size_t begin = scene.find(key) + key.size();
  scene.replace(begin, scene.find('"', begin) - begin, "<script>alert('x')</script> & <b>bold</b>");
  std::ofstream(dir_ / "evil.json") << scene;
  const fs::path out = dir_ / "report";
  const CommandRun r = run("report --quick -o " + out.string() + " " + (dir_ / "evil.json").string());
  ASSERT_EQ(r.status, 0) << r.output;
  const std::string html = read(out / "index.html");
  EXPECT_NE(html.find("&lt;script&gt;alert(&#39;x&#39;)&lt;/script&gt; &amp; &lt;b&gt;bold&lt;/b&gt;"), std::string::npos);
  EXPECT_EQ(html.find("<script>alert"), std::string::npos);
  EXPECT_EQ(html.find("<b>bold"), std::string::npos);
}

}  // namespace
