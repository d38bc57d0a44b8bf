#pragma once
// A test suite with a real headless OpenGL 4.5 context (EGL; llvmpipe here,
// a GPU where one is present), created once per suite.

#include <gtest/gtest.h>

#include <memory>

#include "caustix/runtime/gl_context.h"

namespace caustix::test {

class GlTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    auto ctx = runtime::HeadlessContext::create();
    ASSERT_TRUE(ctx.ok()) << ctx.error().message;
    context_ = std::move(*ctx);
  }
  static void TearDownTestSuite() { context_.reset(); }

 private:
  inline static std::unique_ptr<runtime::HeadlessContext> context_;
};

}  // namespace caustix::test
