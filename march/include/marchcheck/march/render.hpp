// The tile-parallel renderer: marches every pixel of a scene, shades it, and keeps per-stage cost.
#pragma once

#include "marchcheck/march/camera.hpp"
#include "marchcheck/march/marcher.hpp"
#include "marchcheck/sdf/scene.hpp"
#include "marchcheck/sdf/tape.hpp"

#include <cstdint>
#include <functional>
#include <optional>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace marchcheck::march {

// The scene's field as a callable for the marchers and normal estimators, in any scalar type.
struct TapeField {
  const sdf::Tape* tape;
  template <class T>
  T operator()(glm::vec<3, T> p) const {
    return sdf::evaluate(*tape, p);
  }
};

// Image memory: a block of 2 MiB or more on the kernel's 2 MiB pages where it allows them (transparent huge pages
// on request, Debian's default), aligned and rounded to them so that no part of it is left on 4 KiB pages. Filling
// lee-flat's 1280x720 colour image 4 KiB page by page took one thread 16 ms of page faults before the tiles
// started; with only its 2 MiB-aligned middle advised (the head and tail on 4 KiB pages), 2 to 8 ms by where
// the block fell.
void* allocate_pixels(std::size_t bytes);
void free_pixels(void* block, std::size_t bytes);
template <class T>
struct PixelAllocator {
  using value_type = T;
  PixelAllocator() = default;
  template <class U>
  PixelAllocator(const PixelAllocator<U>&) {}
  T* allocate(std::size_t n) { return static_cast<T*>(allocate_pixels(n * sizeof(T))); }
  void deallocate(T* block, std::size_t n) { free_pixels(block, n * sizeof(T)); }
  // A sample made without a value is left unset (Image::unset), not zeroed; one made with a value holds it.
  template <class U>
  void construct(U* at) noexcept {
    ::new (static_cast<void*>(at)) U;
  }
  template <class U, class A>
  void construct(U* at, A&& value) {
    ::new (static_cast<void*>(at)) U(std::forward<A>(value));
  }
  friend bool operator==(const PixelAllocator&, const PixelAllocator&) { return true; }
};

struct Image {
  int width = 0, height = 0, channels = 0;
  std::vector<float, PixelAllocator<float>> pixels;
  Image() = default;
  Image(int w, int h, int c, float fill = 0);  // every channel of every pixel `fill`
  // Every sample left unset, for a writer that sets each one: the renderer's tiles, so that no thread fills the
  // image before they start, and each tile's pages are first touched by the thread that writes them.
  static Image unset(int w, int h, int c);
  float* at(int x, int y) { return &pixels[(static_cast<size_t>(y) * width + x) * channels]; }
  const float* at(int x, int y) const { return &pixels[(static_cast<size_t>(y) * width + x) * channels]; }
};

// error: the largest colour difference from a reference render, which march cannot make (the references live in
// validation): whoever asks for it passes the difference image to write_render.
enum class Aov { depth, normal, steps, evals, id, stages, error };
// Parses "depth,normal,..."; throws std::invalid_argument naming a bad entry.
std::vector<Aov> parse_aovs(const std::string& list);
std::string to_string(Aov aov);

struct StageCost {
  std::uint64_t evals = 0;
  double seconds = 0;
};

struct RenderResult {
  Image color;   // linear RGB
  sdf::OutputTransfer transfer = sdf::OutputTransfer::srgb;  // how its 8-bit files encode it (the scene's)
  Image depth;   // distance along the ray; +inf where nothing was hit
  Image normal;  // unit normal, zero where nothing was hit
  Image steps;   // primary march steps
  Image evals;   // SDF evaluations spent on the pixel, all stages
  Image stage_evals;                    // the same per stage, one channel each
  std::vector<std::string> stage_names;  // channel names of stage_evals
  Image id;      // material index, -1 where nothing was hit
  Image outcome;  // march::Outcome as a number
  std::map<std::string, StageCost> stages;
  int steps_max = 0;  // the most primary march steps of any pixel, kept even where the steps image is not
  std::uint64_t total_evals = 0;
  double seconds = 0;
  double evals_per_pixel() const;
};

// Exact answers that replace marching, for reference renders: the first surface along a unit-length ray
// within t_max (distance and outward normal), or nothing.
struct SurfaceOracle {
  struct Hit {
    double t;
    glm::dvec3 normal;
    double t_error = 0;  // a bound on |t - the exact t| beyond double rounding (a bisection's half width, say)
  };
  std::function<std::optional<Hit>(glm::dvec3 origin, glm::dvec3 direction, double t_max)> first_hit;
};

// Renders at the scene's width and height. Only what the scene declares (and the AOVs asked for) is computed:
// an undeclared stage spends no evaluation and no time. With an oracle, primary hits, normals and hard
// shadows come from it instead of the marcher, shading uses the camera's true eye, and the effects that only
// marching defines (step-count occlusion, glow, sampled occlusion, bounces) are left out.
//
// images = all fills every image of RenderResult; images = asked fills the colour and only the AOVs asked for,
// leaving the others empty (0x0): the per-pixel writes and page faults of unread images are most of a fast
// render's time otherwise.
//
// shade: the arithmetic of the primary hits' shading. single (float) draws the same 8-bit image as dual (double)
// but for pixels on a rounding boundary (test_render.cpp states how many), at a fraction of the cost; dual is
// the reference that claim is tested against. Secondary rays shade in double either way.
enum class Images { all, asked };
enum class ShadePrecision { float32, float64 };
RenderResult render(const sdf::Scene& scene, const std::vector<Aov>& aovs = {}, const SurfaceOracle* oracle = nullptr,
                    Images images = Images::all, ShadePrecision shade = ShadePrecision::float32);

// Keeps the memory a render frees for the next one, for the rest of the process (glibc's allocator; elsewhere
// nothing). Otherwise glibc maps a large block afresh or hands it back, as its sliding thresholds have it, and a
// render whose image lands on fresh pages pays their faults: crum-torus at 640 wide took 0.012 s against 0.005 s,
// and which renders of a sweep paid it depended on what ran before them. Call it before renders that are compared.
void keep_freed_memory();

// Joins render's worker threads (TBB's); call it before the process exits. Workers left to wind down during exit
// race LeakSanitizer's exit-time check, whose tracer then crashes ("Tracer caught signal 11"). False while
// parallel work is still running (the workers then stay); the next render starts workers anew.
bool join_render_workers();

// Dotted cost metrics: cost.stages.<stage>.evals/.seconds, cost.evals_per_pixel, cost.steps_max, cost.seconds.
std::map<std::string, double> cost_metrics(const RenderResult& result);

// Writes the colour image (PNG: 8-bit, by the scene's output transfer; EXR: float linear) and each AOV next to it
// (FILE.depth.exr, FILE.normal.png, FILE.steps.png heat map, FILE.evals.png heat map, FILE.id.png,
// FILE.evals-STAGE.png heat map for each stage that spent evaluations, FILE.error.png heat map of error over
// [0, kErrorHeatMapMax]), each through a temporary file renamed into place. Throws std::runtime_error naming the
// file on failure, std::invalid_argument when the error AOV is asked for without its image.
void write_render(const RenderResult& result, const std::string& path, const std::vector<Aov>& aovs,
                  const Image* error = nullptr);

// The colour difference at the top of the error heat map (the report's and --aov error's).
constexpr double kErrorHeatMapMax = 0.25;

// Writes an image through a temporary file renamed into place; PNG/JPEG get 8-bit sRGB (or raw 8-bit: srgb =
// false, for data images and scenes whose output transfer is linear), saying which in the file's metadata
// (marchcheck:transfer "srgb" or "linear"; sRGB images also carry PNG's sRGB chunk); EXR/TIFF float.
void write_image(const Image& image, const std::string& path, bool srgb = true);

// An 8-bit image's samples, on 2 MiB pages as an Image's pixels are (lee-flat's 1280x720 bytes on 4 KiB pages
// faulted in 3 to 9 ms, by where the block fell).
using Bytes = std::vector<unsigned char, PixelAllocator<unsigned char>>;

// The bytes write_image puts in an 8-bit file: sRGB-encoded (or clamped raw values: srgb = false), rounded.
Bytes to_8bit(const Image& image, bool srgb = true);

// A heat map (dark blue to yellow) of a one-channel image over [0, max_value].
Image heat_map(const Image& values, double max_value);

}  // namespace marchcheck::march
