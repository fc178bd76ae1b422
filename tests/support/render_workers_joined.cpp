// Linked into the test executables that render: each joins the render's worker threads before it exits (see
// march::join_render_workers), as the marchcheck program does.
#include "marchcheck/march/render.hpp"

#include <gtest/gtest.h>

namespace {
class RenderWorkersJoined : public testing::Environment {
 public:
  void TearDown() override { marchcheck::march::join_render_workers(); }
};
// gtest owns the environment.
[[maybe_unused]] const testing::Environment* const kRenderWorkersJoined =
    testing::AddGlobalTestEnvironment(new RenderWorkersJoined);
}  // namespace
