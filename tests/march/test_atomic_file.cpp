// Whole files or none: a write that fails leaves the previous file as it was and no temporary behind.
#include "marchcheck/files/atomic_file.hpp"
#include "marchcheck/march/render.hpp"
#include "file_size_limit.hpp"
#include "srgb.hpp"

#include <gtest/gtest.h>

#include <png.h>

#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <stdexcept>

namespace marchcheck::march {
namespace {

namespace fs = std::filesystem;
using files::temp_name;
using files::write_atomically;
using files::write_bytes_atomically;

class AtomicFile : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("marchcheck_atomic_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  static std::string read(const std::string& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
  }
  // The check every test below makes: after a failed write, path holds what it held before and the folder
  // holds nothing else.
  ::testing::AssertionResult left_as_before(const std::string& p, const std::string& before) const {
    if (read(p) != before) return ::testing::AssertionFailure() << p << " now holds '" << read(p) << "'";
    for (const auto& entry : fs::directory_iterator(dir_))
      if (entry.path().string() != p) return ::testing::AssertionFailure() << "left behind: " << entry.path();
    return ::testing::AssertionSuccess();
  }
  fs::path dir_;
};

// A writer that fails halfway: some bytes are out, then it throws (a full disk, an exception mid-render).
void half_then_throw(const std::string& target) {
  std::ofstream(target, std::ios::binary) << "half a fi";
  throw std::runtime_error("disk full");
}

TEST_F(AtomicFile, TempNameIsHiddenInTheSameFolderWithTheSameExtension) {
  const std::string pid = std::to_string(::getpid());
  EXPECT_EQ(temp_name("out/a.png"), "out/.a.png.tmp-" + pid + ".png");
  EXPECT_EQ(temp_name("v.json"), ".v.json.tmp-" + pid + ".json");
}

TEST_F(AtomicFile, ReplacesTheFileWhenTheWriteSucceeds) {
  std::ofstream(path("r.json")) << "old";
  write_atomically(path("r.json"), [](const std::string& tmp) { std::ofstream(tmp) << "new"; });
  EXPECT_EQ(read(path("r.json")), "new");
  EXPECT_TRUE(left_as_before(path("r.json"), "new"));
}

TEST_F(AtomicFile, AWriterThatThrowsHalfwayLeavesThePreviousFileAndNoTemporary) {
  std::ofstream(path("r.json")) << "previous results";
  try {
    write_atomically(path("r.json"), half_then_throw);
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), path("r.json") + ": disk full");
  }
  EXPECT_TRUE(left_as_before(path("r.json"), "previous results"));
}

TEST_F(AtomicFile, AFailedRenameLeavesTheTargetAndNoTemporary) {
  // A non-empty folder in the way: rename(2) refuses even for root, unlike a read-only folder.
  fs::create_directories(path("busy.json"));
  std::ofstream(path("busy.json") + "/inside") << "kept";
  try {
    write_atomically(path("busy.json"), [](const std::string& tmp) { std::ofstream(tmp) << "new"; });
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()).rfind(path("busy.json") + ": cannot move the finished file into place: ", 0), 0u)
        << e.what();
  }
  EXPECT_EQ(read(path("busy.json") + "/inside"), "kept");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()), 1);
}

TEST_F(AtomicFile, AMissingFolderGivesAnErrorNamingThePath) {
  EXPECT_THROW(write_image(Image(4, 4, 3), path("no/such/folder/a.png")), std::runtime_error);
  EXPECT_FALSE(fs::exists(path("no")));
}

TEST_F(AtomicFile, AFailedImageWriteKeepsThePreviousImage) {
  const Image image(4, 4, 3, 0.5f);
  write_image(image, path("a.png"));
  const std::string before = read(path("a.png"));
  ASSERT_FALSE(before.empty());
  // OIIO picks the writer from the temporary's extension; an unknown one fails before any byte is written.
  fs::rename(path("a.png"), path("a.nope"));
  try {
    write_image(image, path("a.nope"));
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()).rfind(path("a.nope") + ": no image writer for this extension", 0), 0u) << e.what();
  }
  EXPECT_TRUE(left_as_before(path("a.nope"), before));
}

// A PNG as libpng reads it back: its 8-bit samples, channel count, transfer text and whether it has an sRGB chunk.
struct ReadPng {
  Bytes samples;
  int channels = 0;
  std::string transfer;
  bool srgb_chunk = false;
};
ReadPng read_png(const std::string& path) {
  ReadPng out;
  FILE* file = std::fopen(path.c_str(), "rb");
  if (!file) return out;
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_read_struct(&png, &info, nullptr);
    std::fclose(file);
    return {};
  }
  png_init_io(png, file);
  png_read_png(png, info, PNG_TRANSFORM_IDENTITY, nullptr);
  out.channels = png_get_channels(png, info);
  const png_bytepp rows = png_get_rows(png, info);
  const size_t row = png_get_rowbytes(png, info);
  for (png_uint_32 y = 0; y < png_get_image_height(png, info); ++y) out.samples.insert(out.samples.end(), rows[y], rows[y] + row);
  png_textp text = nullptr;
  int count = 0;
  png_get_text(png, info, &text, &count);
  for (int i = 0; i < count; ++i)
    if (std::string(text[i].key) == "marchcheck:transfer") out.transfer = text[i].text;
  int intent = 0;
  out.srgb_chunk = png_get_sRGB(png, info, &intent) != 0;
  png_destroy_read_struct(&png, &info, nullptr);
  std::fclose(file);
  return out;
}

// A PNG holds exactly to_8bit's bytes, for grey, grey and alpha, RGB and RGBA images, with the transfer it was
// written in (tEXt marchcheck:transfer) and an sRGB chunk only for sRGB. Broken variants: rows written from the
// wrong offset (march-png-row-stride), the sRGB chunk on raw values too (march-png-srgb-always).
TEST_F(AtomicFile, APngHoldsTheEightBitBytesAndItsTransfer) {
  for (int channels = 1; channels <= 4; ++channels)
    for (const bool srgb : {true, false}) {
      Image image(5, 3, channels);
      for (size_t i = 0; i < image.pixels.size(); ++i) image.pixels[i] = static_cast<float>(i % 17) / 16;
      write_image(image, path("c.png"), srgb);
      const ReadPng back = read_png(path("c.png"));
      EXPECT_EQ(back.channels, channels);
      EXPECT_EQ(back.samples, to_8bit(image, srgb)) << channels << " channels, srgb " << srgb;
      EXPECT_EQ(back.transfer, srgb ? "srgb" : "linear");
      EXPECT_EQ(back.srgb_chunk, srgb);
    }
}

// A PNG larger than one piece of the parallel deflate (about 128 KiB of filtered rows) reads back whole: 640x240 RGB
// (461 KiB, four pieces) and RGBA, with samples that wrap around in the Sub filter. Broken variants: every piece
// ended as the last (march-png-every-piece-final: a reader stops after the first), the pieces' checksums not
// combined (march-png-adler-of-last-piece), the Sub filter one sample off (march-png-sub-filter-offset).
TEST_F(AtomicFile, APngOfManyDeflatePiecesReadsBackWhole) {
  for (const int channels : {3, 4}) {
    Image image(640, 240, channels);
    std::uint32_t state = 12345;
    for (float& v : image.pixels) {
      state = state * 1664525u + 1013904223u;  // a linear congruential sequence: any sample next to any other
      v = static_cast<float>(state >> 8) / static_cast<float>(1u << 24);
    }
    write_image(image, path("big.png"), false);
    const ReadPng back = read_png(path("big.png"));
    EXPECT_EQ(back.channels, channels);
    EXPECT_TRUE(back.samples == to_8bit(image, false)) << channels << " channels: " << back.samples.size() << " samples read";
  }
}

// to_8bit rounds v * 255 as std::lround does (halves up), on the values where a shortcut would differ: each level's
// half-way point and its neighbouring floats, and the float just below 0.5 / 255 (0.49999997f + 0.5f is 1 in
// float). Broken variant: the rounding done in float (march-8bit-rounding-in-float).
TEST(EightBit, RoundsAsLroundAtEveryHalfWayPoint) {
  Image image(0, 1, 1);
  for (int level = 0; level < 255; ++level) {
    float v = (static_cast<float>(level) + 0.5f) / 255.0f;
    for (int k = 0; k < 4; ++k) v = std::nextafter(v, 0.0f);
    for (int k = 0; k < 9; ++k, v = std::nextafter(v, 1.0f)) image.pixels.push_back(v);
  }
  image.pixels.push_back(std::nextafter(0.5f, 0.0f) / 255.0f);
  image.width = static_cast<int>(image.pixels.size());
  const Bytes bytes = to_8bit(image, false);
  ASSERT_EQ(bytes.size(), image.pixels.size());
  int differ = 0;
  for (size_t i = 0; i < bytes.size(); ++i) differ += bytes[i] != std::lround(image.pixels[i] * 255.0f);
  EXPECT_EQ(differ, 0) << "of " << bytes.size();
  EXPECT_EQ(bytes.back(), 0);
}

// to_8bit's sRGB byte is the curve's, rounded, for every float from 4096 below the curve's power part to 4096 above 1
// (71 million: the part of [0, 1] where to_8bit reads the bytes from a table, which assumes they never fall as the
// value rises; this is where that is checked), and for NaN, infinities, negatives and denormals. Broken variant:
// each byte's first float given the byte below (march-srgb-step-one-late).
TEST(EightBit, SrgbBytesAreTheCurvesForEveryFloatOfItsPowerPart) {
  const auto curve = [](float value) {
    const float v = marchcheck::testing::to_srgb(std::isnan(value) ? 0.0f : value);
    return static_cast<unsigned char>(std::floor(static_cast<double>(v * 255.0f) + 0.5));
  };
  const std::uint32_t low = std::bit_cast<std::uint32_t>(0.0031308f) - 4096, high = std::bit_cast<std::uint32_t>(1.0f) + 4096;
  constexpr std::uint32_t kChunk = 1u << 22;
  Image image(static_cast<int>(kChunk), 1, 1);
  size_t checked = 0, differ = 0;
  for (std::uint32_t first = low; first < high; first += kChunk) {
    const std::uint32_t n = std::min(kChunk, high - first);
    image.width = static_cast<int>(n);
    image.pixels.resize(n);
    for (std::uint32_t i = 0; i < n; ++i) image.pixels[i] = std::bit_cast<float>(first + i);
    const Bytes bytes = to_8bit(image, true);
    for (std::uint32_t i = 0; i < n; ++i) differ += bytes[i] != curve(image.pixels[i]);
    checked += n;
  }
  EXPECT_EQ(differ, 0u) << "of " << checked;
  const float inf = std::numeric_limits<float>::infinity();
  Image special(8, 1, 1);
  special.pixels = {std::nanf(""), -inf, inf, -0.0f, -1.0f, 2.0f, std::numeric_limits<float>::denorm_min(), 0.0031308f};
  const Bytes bytes = to_8bit(special, true);
  for (size_t i = 0; i < bytes.size(); ++i) EXPECT_EQ(bytes[i], curve(special.pixels[i])) << special.pixels[i];
}

// OpenImageIO is loaded where it is used, not by every command (Debian's build brings ~260 libraries, 160 ms): a
// PNG is written without it in the process, an EXR brings its module in. Broken variant: PNGs written through
// OpenImageIO again (march-png-through-openimageio).
TEST_F(AtomicFile, APngIsWrittenWithoutLoadingOpenImageIO) {
  const auto loaded = [] {
    std::ifstream maps("/proc/self/maps");
    return std::string(std::istreambuf_iterator<char>(maps), {}).find("libOpenImageIO") != std::string::npos;
  };
  // ctest runs each test in a process of its own; all of test_march in one process has loaded it by now.
  if (loaded()) GTEST_SKIP() << "an earlier test in this process loaded OpenImageIO";
  write_image(Image(4, 4, 3, 0.5f), path("a.png"));
  EXPECT_FALSE(loaded());
  write_image(Image(4, 4, 3, 0.5f), path("a.exr"));
  EXPECT_TRUE(loaded());
}

// A 1 KiB file-size limit on 4 KiB of bytes: the disk fills after the file was opened and partly written (at
// close, as buffered bytes go out). Broken variant: the stream's state after close() not checked.
TEST_F(AtomicFile, BytesWrittenUnderAFullDiskLeaveThePreviousFile) {
  write_bytes_atomically(path("r.json"), "{\"old\": true}\n");
  EXPECT_EQ(write_under_file_size_limit(1024, [&] { write_bytes_atomically(path("r.json"), std::string(4096, 'x')); }),
            LimitedWrite::threw);
  EXPECT_TRUE(left_as_before(path("r.json"), "{\"old\": true}\n"));
}

// The disk fills after the image file was opened and partly written (a 1 KiB file-size limit on a 64x64 PNG of
// noise, ~12 KiB): the writer must fail and the previous image stay. Broken variant: close()'s failure ignored.
TEST_F(AtomicFile, AnImageWriteThatFailsLateKeepsThePreviousImage) {
  Image noise(64, 64, 3);
  for (size_t i = 0; i < noise.pixels.size(); ++i) noise.pixels[i] = static_cast<float>((i * 2654435761u) % 1000) / 1000;
  write_image(Image(4, 4, 3, 0.5f), path("a.png"));
  const std::string before = read(path("a.png"));
  EXPECT_EQ(write_under_file_size_limit(1024, [&] { write_image(noise, path("a.png")); }), LimitedWrite::threw);
  EXPECT_TRUE(left_as_before(path("a.png"), before));
}

// The broken variants the check above must catch: writing in place, and a temporary left behind.
TEST_F(AtomicFile, TheCheckCatchesAWriterThatWritesInPlaceOrLeavesItsTemporary) {
  std::ofstream(path("r.json")) << "previous results";
  EXPECT_THROW(half_then_throw(path("r.json")), std::runtime_error);  // no temp + rename: in place
  EXPECT_FALSE(left_as_before(path("r.json"), "previous results"));

  std::ofstream(path("s.json")) << "previous results";
  EXPECT_THROW(half_then_throw(temp_name(path("s.json"))), std::runtime_error);  // no cleanup
  fs::remove(path("r.json"));
  EXPECT_FALSE(left_as_before(path("s.json"), "previous results"));
}

}  // namespace
}  // namespace marchcheck::march
