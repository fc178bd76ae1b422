// The certified reference and the certified Lipschitz constant on a field whose constant is understated: a slab
// 0.05 thick seen through a squash that makes its field 4-Lipschitz, marched as if it were 2-Lipschitz (half the
// true constant). Steps of f / 2 from below jump the slab. The broken variant the certified reference replaces,
// the L-stepping numerical reference trusting the same 2, jumps it too and would call every such miss right.
#include "marchcheck/validation/certified.hpp"
#include "marchcheck/validation/reference.hpp"
#include "marchcheck/validation/slice.hpp"
#include "marchcheck/validation/validate.hpp"

#include "marchcheck/march/camera.hpp"
#include "marchcheck/march/marcher.hpp"
#include "marchcheck/march/render.hpp"
#include "marchcheck/sdf/interval.hpp"

#include <gtest/gtest.h>

namespace marchcheck::validation {
namespace {

using glm::dvec3;

constexpr double kTrueL = 4, kUnderstated = 2;

sdf::Node thin_slab() {
  return sdf::make(sdf::Op::affine, {{"model", {1, 0, 0, 0, 0, 0.25, 0, 0, 0, 0, 1, 0}}}, {sdf::box({2, 0.1, 2})});
}

// Looking up at the slab (|y| < 0.025) from y = -3, marched by steps of f / L with the subject's L.
sdf::Scene slab_scene() {
  sdf::Scene s;
  s.name = "thin-slab";
  s.root = thin_slab();
  s.camera.position = {0, -3, 0.01};
  s.camera.target = {0, 0, 0};
  s.camera.up = {0, 0, 1};
  s.camera.fov_deg = 40;
  s.width = 160;
  s.height = 90;
  s.march.marcher = sdf::Marcher::scaled;
  s.march.max_dist = 10;
  s.march.hit_eps = 1e-4;
  s.lights.clear();
  return s;
}

// The scene's own subject, declaring and marching with the understated constant.
Subject understated_subject(const sdf::Scene& s) {
  Subject subject = scene_subject(s);
  subject.declared.lipschitz = kUnderstated;
  const auto tape = std::make_shared<const sdf::Tape>(sdf::compile(s.root, s.time));
  const march::MarchContext ctx = march::march_context(march::Camera(s.camera, s.width, s.height), kUnderstated);
  const sdf::MarchSettings settings = s.march;
  subject.march = [tape, ctx, settings](dvec3 o, dvec3 d) {
    const auto r = march::march<double>(march::TapeField{tape.get()}, o, d, settings, ctx);
    return MarchedRay{r.outcome, r.t, r.evals, std::nullopt};
  };
  subject.visibility = nullptr;
  return subject;
}

TEST(CertifiedReference, FindsTheThinSlabThatStepsByAnUnderstatedConstantJump) {
  ASSERT_NEAR(sdf::derive_info(thin_slab(), 0).lipschitz, kTrueL, 1e-12);
  const dvec3 o(0.3, -1, 0.2), up(0, 1, 0);
  const CertifiedHit c = certified_first_hit(sdf::compile(thin_slab()), o, up, 10);
  ASSERT_EQ(c.verdict, CertifiedHit::Verdict::hit);
  // The slab's lower face is at y = -0.025: t = 0.975, inside the certified bracket of width <= 1e-7 (1 + t).
  EXPECT_LE(c.t_lo, 0.975);
  EXPECT_GE(c.t_hi, 0.975);
  EXPECT_LE(c.t_hi - c.t_lo, kCertifiedWidth * (1 + c.t_lo));
  // The broken variant: the numerical reference stepping by the understated 2 goes from y = -1 to 0.95.
  const Reference trusting(thin_slab(), 0, kUnderstated);
  EXPECT_FALSE(trusting.numerical_first_hit(o, up, 10).hit);
  EXPECT_TRUE(trusting.first_hit(o, up, 10).hit);  // certified: the constant is not trusted
}

// A ray that starts on a plane and runs along it (f = 0 all the way, to rounding) cannot be decided: the
// reference says so, and the numerical answer that stands in for it is marked as such.
TEST(CertifiedReference, ARayAlongTheSurfaceIsUndecidableAndSaysSo) {
  const sdf::Node field = sdf::smooth_union(1e-6, {sdf::plane({0, 1, 0}, 0), sdf::translate({100, 0, 0}, sdf::sphere(0.1))});
  const Reference ref(field, 0);
  ASSERT_EQ(ref.kind(), ReferenceKind::certified);
  EXPECT_EQ(certified_first_hit(sdf::compile(field), {0, 0, 0}, {1, 0, 0}, 10).verdict,
            CertifiedHit::Verdict::undecidable);
  EXPECT_TRUE(ref.first_hit({0, 0, 0}, {1, 0, 0}, 10).undecided);
  EXPECT_FALSE(ref.first_hit({0, 1, 0}, {0, -1, 0}, 10).undecided);  // straight down onto it: decided
}

// A ray that just touches a sphere (radius 0.7: its square is not a double, so the field at the touch is an
// interval around 0) touches without crossing: no proven hit, however fine the segment.
TEST(CertifiedReference, ATouchIsNoHit) {
  const sdf::Node field = sdf::smooth_union(1e-6, {sdf::sphere(0.7), sdf::translate({100, 0, 0}, sdf::sphere(0.1))});
  const CertifiedHit c = certified_first_hit(sdf::compile(field), {-2, 0.7, 0}, {1, 0, 0}, 4);  // touches at t = 2
  EXPECT_NE(c.verdict, CertifiedHit::Verdict::hit);
  // The proof stops where it can no longer tell the field from 0: within the certified width of the touch.
  EXPECT_NEAR(c.t_lo, 2, 1e-6);
}

TEST(CertifiedReference, AMarcherTrustingAnUnderstatedConstantIsCaughtAndTheConstantExposed) {
  const sdf::Scene s = slab_scene();
  ValidateOptions options;
  options.rays_x = 16;
  options.rays_y = 9;
  const SceneResult r = validate_subject(s, understated_subject(s), options);
  EXPECT_EQ(r.reference, "certified");
  // Every ray the camera casts crosses the slab at |x|, |z| < 2: each jumps it, each is a false miss.
  EXPECT_EQ(metric_value(r.metrics, "hit.false_miss"), 144);
  // The numerical reference, trusting the 2, misses as the marcher does: it disagrees on every ray.
  EXPECT_EQ(metric_value(r.metrics, "reference.numerical_disagree"), 144);
  EXPECT_EQ(metric_value(r.metrics, "reference.undecidable"), 0);
  // The certified bound over the camera's region is at least the true 4 (the slab's gradient), and the proven
  // slope (a difference quotient with interval values) exceeds the declared 2: understated, not just unproven.
  EXPECT_GE(metric_value(r.metrics, "sdf.lipschitz_certified"), kTrueL);
  EXPECT_GT(metric_value(r.metrics, "sdf.lipschitz_proven_lower"), kUnderstated);
  EXPECT_GT(metric_value(r.metrics, "sdf.lipschitz_certified_over_declared"), 1.001);
  EXPECT_NE(r.offenders.at("sdf.lipschitz_certified_over_declared").find("understated"), std::string::npos);
}

// Declared at its true 4, the same field's constant is proven along rays through the slab, past its edge and
// along its face (the bound over every piece at most 4.004); at 2 it is not, and the slope proves why.
TEST(CertifiedLipschitz, ProvesTheTrueConstantAlongRaysAndShowsAnUnderstatedOneUnderstated) {
  const std::vector<RayPath> paths = {{{0.3, -1, 0.2}, {0, 1, 0}, 3},
                                      {{-3, -1, 0}, glm::normalize(dvec3(1, 0.4, 0.1)), 8},
                                      {{-3, -0.03, 0.5}, {1, 0, 0}, 6}};
  const sdf::Tape tape = sdf::compile(thin_slab());
  const CertifiedLipschitz c = certify_lipschitz(tape, paths, 1.001 * kTrueL);
  EXPECT_EQ(c.unproven, 0);
  EXPECT_LE(c.upper, 1.001 * kTrueL);
  EXPECT_GE(c.upper, kTrueL);  // no piece through the slab can bound its slope below the true value
  const CertifiedLipschitz under = certify_lipschitz(tape, paths, 1.001 * kUnderstated);
  EXPECT_GT(under.unproven, 0);
  EXPECT_GT(under.lower, kUnderstated);
  EXPECT_LE(under.lower, kTrueL * (1 + 1e-9));  // a proven slope never exceeds the true constant
}

// A twisted box's gradient bound over a long piece of a ray is loose (the twist's angle spans a wide interval)
// and tight over short ones: the pieces are halved until each is proven, and the declared constant is.
TEST(CertifiedLipschitz, RefinesWhereTheBoundIsLoose) {
  const sdf::Node twisted = sdf::make(sdf::Op::twist, {{"rate", {1.5}}}, {sdf::box({0.5, 1, 0.3})});
  const double declared = sdf::derive_info(twisted, 0).lipschitz;
  std::vector<RayPath> paths;
  for (int i = 0; i < 8; ++i)
    paths.push_back({{-3, -1 + 0.25 * i, 0.1}, glm::normalize(dvec3(1, 0.05, 0.02 * i)), 6});
  const CertifiedLipschitz c = certify_lipschitz(sdf::compile(twisted), paths, kLipschitzTolerance * declared);
  EXPECT_EQ(c.unproven, 0);
  EXPECT_LE(c.upper, kLipschitzTolerance * declared);
  EXPECT_GT(c.boxes, 4 * static_cast<int>(paths.size()));  // refined: more than a couple of pieces per path
}

// The slice across the slab (the plane z = 0.01 through the camera's target): both panels, the zero contour
// white where the slab's faces cross it, and the certified squares: every bound at least the slab's slope 4
// where a square meets it, none over the declared (true) constant.
TEST(Slice, DrawsTheSlabWithItsContourAndCertifiedSquares) {
  sdf::Scene s = slab_scene();
  const Slice sl = slice(s, parse_plane("z=0.01"), 64, 64);
  EXPECT_EQ(sl.image.width, 128);
  EXPECT_EQ(sl.image.height, 64);
  ASSERT_TRUE(sl.certified);
  EXPECT_EQ(sl.cells, 32 * 32);
  EXPECT_EQ(sl.cells_over, 0);
  EXPECT_GE(sl.steepest_bound, kTrueL);
  EXPECT_LE(sl.steepest_bound, kLipschitzTolerance * kTrueL);
  int white = 0;  // the contour: the slab's two faces, a row or two each across the 64 columns
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) white += sl.image.at(x, y)[0] == 1.f && sl.image.at(x, y)[2] == 1.f;
  EXPECT_GE(white, 2 * 64);
  EXPECT_THROW(parse_plane("w=1"), std::invalid_argument);
  EXPECT_THROW(parse_plane("y=1e999"), std::invalid_argument);
  EXPECT_EQ(parse_plane("x=-0.5").axis, 0);
}

}  // namespace
}  // namespace marchcheck::validation
