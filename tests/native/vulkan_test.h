#pragma once
// Every native test runs on one shared Vulkan context with the Khronos
// validation layer on; a test fails if validation said anything during it.
#include <gtest/gtest.h>

#include <cstdlib>
#include <memory>
#include <string>

#include "vk/context.h"

namespace rtsdf::testing {

// The real mesh the mesh tests measure: RTSDF_TEST_MESH=FILE (e.g. a held-out
// model), else the bundled sample.
inline std::string test_mesh_path() {
  const char* path = std::getenv("RTSDF_TEST_MESH");
  return path && *path ? path : RTSDF_SAMPLE_MESH;
}

class VulkanTest : public ::testing::Test {
 public:
  static vk::Context& context() {
    static std::unique_ptr<vk::Context> shared = [] {
      vk::ContextOptions options = vk::ContextOptions::from_environment();
      options.validation = true;
      return std::make_unique<vk::Context>(options);
    }();
    return *shared;
  }

 protected:
  void SetUp() override { messages_before_ = context().validation_message_count(); }
  void TearDown() override {
    EXPECT_EQ(context().validation_message_count(), messages_before_) << "Vulkan validation reported problems";
  }

 private:
  int messages_before_ = 0;
};

}  // namespace rtsdf::testing
