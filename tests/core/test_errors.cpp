// The typed errors: each derives from the standard exception callers caught before, the checks
// throw the kind they say, and the rethrow helpers keep or convert the kind as documented.

#include <gtest/gtest.h>

#include <new>
#include <string>

#include "fmcw/core/check.hpp"
#include "fmcw/core/errors.hpp"
#include "fmcw/core/grid_projection.hpp"
#include "fmcw/core/head_model.hpp"

namespace fmcw::core {
namespace {

// The message of the error fn throws as Error, or "" (a test failure) when it throws none.
template <typename Error, typename Fn>
std::string message_of(Fn fn) {
  try {
    fn();
  } catch (const Error& e) {
    return e.what();
  }
  ADD_FAILURE() << "no error thrown";
  return "";
}

TEST(Errors, EachKindIsTheStandardExceptionCallersCaughtBefore) {
  static_assert(std::is_base_of_v<std::invalid_argument, InputError>);
  static_assert(std::is_base_of_v<std::invalid_argument, FileError>);
  static_assert(std::is_base_of_v<std::runtime_error, LimitError>);
  static_assert(!std::is_base_of_v<std::invalid_argument, LimitError>);
  EXPECT_THROW(FMCW_CHECK_ARG(1 > 2, "x: ", 3), InputError);
  EXPECT_THROW(FMCW_CHECK_FILE(1 > 2, "f.pcd: bad"), FileError);
  EXPECT_THROW(FMCW_CHECK_LIMIT(1 > 2, "too big"), LimitError);
  EXPECT_EQ(message_of<std::invalid_argument>([] { FMCW_CHECK_ARG(1 > 2, "x: ", 3, " is wrong"); }),
            "x: 3 is wrong (failed: 1 > 2)");
}

TEST(Errors, ABadParameterIsAnInputErrorAndTooManyPixelsALimitError) {
  HeadModel head;
  head.name = "roof";
  head.rate_hz = -10.0;
  EXPECT_NE(message_of<InputError>([&] { head.validate(); }).find("head 'roof': rate must be > 0 Hz"), std::string::npos);
  head = HeadModel();
  head.resolution_horizontal_rad = head.resolution_vertical_rad = 1e-6;  // a resolution typed in the wrong unit
  EXPECT_NE(message_of<LimitError>([&] { head.validate(); }).find("more than the 16777216 a head may have"),
            std::string::npos);
  GridProjectionParams grid;
  grid.resolution_horizontal_deg = 1e-6;
  EXPECT_THROW(grid.validate(), LimitError);
}

// A callable that throws error and calls handle() in the catch block.
template <typename Error, typename Handle>
auto thrown_and_handled(Error error, Handle handle) {
  return [error, handle] {
    try {
      throw error;
    } catch (const std::exception&) {
      handle();
    }
  };
}

TEST(Errors, RethrowWithContextKeepsTheKind) {
  const auto with_context = [](auto error) {
    return thrown_and_handled(error, [] { rethrow_with_context("a.yaml: ", " (more)"); });
  };
  EXPECT_EQ(message_of<InputError>(with_context(InputError("bad"))), "a.yaml: bad (more)");
  EXPECT_EQ(message_of<FileError>(with_context(FileError("bad"))), "a.yaml: bad (more)");
  EXPECT_EQ(message_of<LimitError>(with_context(LimitError("big"))), "a.yaml: big (more)");
  EXPECT_EQ(message_of<std::runtime_error>(with_context(std::runtime_error("disk"))), "a.yaml: disk (more)");
  EXPECT_THROW(with_context(std::bad_alloc())(), std::bad_alloc);
}

TEST(Errors, RethrowAsFileErrorBlamesTheFileButKeepsALimit) {
  const auto in_file = [](auto error) { return thrown_and_handled(error, [] { rethrow_as_file_error("a.pcd: "); }); };
  EXPECT_EQ(message_of<FileError>(in_file(InputError("range is 0"))), "a.pcd: range is 0");
  EXPECT_EQ(message_of<FileError>(in_file(std::invalid_argument("range is 0"))), "a.pcd: range is 0");
  EXPECT_EQ(message_of<LimitError>(in_file(LimitError("too many pixels"))), "a.pcd: too many pixels");
  EXPECT_THROW(in_file(std::runtime_error("disk"))(), std::runtime_error);
}

}  // namespace
}  // namespace fmcw::core
