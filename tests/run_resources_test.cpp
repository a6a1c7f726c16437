// Tests of a run's shared resources (core/run_resources.h) and the embree
// rows' one device per run (registry/embree_device.h), issue #22:
//
//   * one run hands every asker the same object for a key, made once; another
//     run makes its own (no global behind it);
//   * a key asked with another type than its resource was made with throws
//     instead of handing back the wrong object;
//   * the Embree device slot is the run's: the same device for every embree
//     session of one run, another for another run, and none made until a
//     frame asks for it.
// The whole-process counts (verify, the property binary) are the CLI tests
// verify.embree_one_device and props.embree_one_device.
#include "core/run_resources.h"

#include <gtest/gtest.h>

#include <memory>
#include <stdexcept>

#include "registry/embree_device.h"

namespace lockstep {
namespace {

std::shared_ptr<int> make_int() { return std::make_shared<int>(7); }
std::shared_ptr<double> make_double() { return std::make_shared<double>(7); }

constexpr RunKey<int> kCount{"count", make_int};
constexpr RunKey<int> kOther{"other", make_int};
constexpr RunKey<double> kCountAsDouble{"count", make_double};

TEST(RunResources, SameObjectForOneKeyInOneRun) {
  RunResources run;
  EXPECT_EQ(run.size(), 0u);
  const auto a = run.get(kCount);
  *a = 42;
  const auto b = run.get(kCount);
  EXPECT_EQ(a, b);
  EXPECT_EQ(*b, 42);  // not made again
  EXPECT_EQ(run.size(), 1u);
  EXPECT_NE(run.get(kOther), a);
  EXPECT_EQ(run.size(), 2u);
}

TEST(RunResources, EachRunItsOwn) {
  RunResources one, two;
  EXPECT_NE(one.get(kCount), two.get(kCount));
}

TEST(RunResources, OutlivesTheHolderWhileHeld) {
  std::shared_ptr<int> kept;
  {
    RunResources run;
    kept = run.get(kCount);
  }
  EXPECT_EQ(*kept, 7);
}

TEST(RunResources, WrongTypeThrows) {
  RunResources run;
  run.get(kCount);
  EXPECT_THROW(run.get(kCountAsDouble), std::logic_error);
}

TEST(EmbreeDevice, OnePerRun) {
  RunResources run, other;
  const auto slot = embree_device(run);
  EXPECT_EQ(embree_device(run), slot);
  EXPECT_NE(embree_device(other), slot);
  const opt::embree::Device d = slot->get();
  ASSERT_NE(d.handle, nullptr);
  EXPECT_EQ(embree_device(run)->get().handle, d.handle);
  EXPECT_NE(embree_device(other)->get().handle, d.handle);
}

}  // namespace
}  // namespace lockstep
