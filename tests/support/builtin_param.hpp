// GoogleTest parameter names for built-in scenes: "lee-flat" becomes "lee_flat" (test names allow no '-').
#pragma once

#include <gtest/gtest.h>

#include <string>

namespace marchcheck::testing {

inline std::string builtin_param_name(const ::testing::TestParamInfo<std::string>& info) {
  std::string name = info.param;
  for (char& c : name)
    if (c == '-') c = '_';
  return name;
}

}  // namespace marchcheck::testing
