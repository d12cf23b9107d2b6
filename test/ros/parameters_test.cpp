#include "surgical_sim/ros/parameters.h"

#include <gtest/gtest.h>

#include <limits>
#include <stdexcept>
#include <string>

namespace surgical_sim::ros_layer {
namespace {

using XmlRpc::XmlRpcValue;

/// Message of the std::invalid_argument that `check` throws ("" if it throws nothing).
template <class Check>
std::string problem(Check check) {
  try {
    check();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

XmlRpcValue list(std::initializer_list<XmlRpcValue> entries) {
  XmlRpcValue l;
  l.setSize(static_cast<int>(entries.size()));
  int i = 0;
  for (const XmlRpcValue& e : entries) l[i++] = e;
  return l;
}

TEST(Parameters, NumberAcceptsIntegersAndFloatsInRange) {
  EXPECT_EQ(checkNumber("x", XmlRpcValue(3), {-10.0, 10.0}, "m"), 3.0);
  EXPECT_EQ(checkNumber("x", XmlRpcValue(-2.5), {-10.0, 10.0}, "m"), -2.5);
  EXPECT_EQ(checkNumber("rate", XmlRpcValue(1000.0), {0.0, 1000.0, true}, "Hz"), 1000.0);
}

TEST(Parameters, NumberOfTheWrongTypeIsAnErrorNotAFallback) {
  const std::string m = problem([] { checkNumber("x", XmlRpcValue("far"), {-10, 10}, "m"); });
  EXPECT_EQ(m, "~x must be a number in [-10, 10] m, got the string 'far'");
  EXPECT_NE(problem([] {
              checkNumber("x", XmlRpcValue(true), {-10, 10}, "m");
            }).find("got the boolean true"),
            std::string::npos);
}

TEST(Parameters, NumberOutOfRangeNamesParameterUnitAndRange) {
  EXPECT_EQ(problem([] {
              checkNumber("rate", XmlRpcValue(5.0), {100, 20000}, "Hz");
            }),
            "~rate = 5 Hz is out of range: must be in [100, 20000] Hz");
  EXPECT_EQ(problem([] {
              checkNumber("stale_age", XmlRpcValue(0.0), {0, 10, true}, "s");
            }),
            "~stale_age = 0 s is out of range: must be in (0, 10] s");
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(problem([nan] {
              checkNumber("z", XmlRpcValue(nan), {-10, 10}, "m");
            }).find("~z = nan m is out of range"),
            std::string::npos);
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_NE(problem([inf] { checkNumber("z", XmlRpcValue(inf), {-1e308, 1e308}, "m"); }), "");
}

TEST(Parameters, IntegerRejectsFloatsAndOutOfRange) {
  EXPECT_EQ(checkInt("steps_per_pose", XmlRpcValue(7), 1, 1000, ""), 7);
  EXPECT_EQ(problem([] { checkInt("steps_per_pose", XmlRpcValue(2.0), 1, 1000, ""); }),
            "~steps_per_pose must be an integer in [1, 1000], got the number 2");
  EXPECT_EQ(problem([] { checkInt("steps_per_pose", XmlRpcValue(0), 1, 1000, ""); }),
            "~steps_per_pose = 0 is out of range: must be in [1, 1000]");
}

TEST(Parameters, BoolStringAndChoiceAreTypeChecked) {
  EXPECT_FALSE(checkBool("realtime", XmlRpcValue(false)));
  EXPECT_EQ(problem([] { checkBool("realtime", XmlRpcValue(1)); }),
            "~realtime must be true or false, got the integer 1");
  EXPECT_EQ(checkString("world_frame", XmlRpcValue("map"), false), "map");
  EXPECT_EQ(checkString("joint_prefix", XmlRpcValue(""), true), "");
  EXPECT_EQ(problem([] { checkString("world_frame", XmlRpcValue(""), false); }),
            "~world_frame must be a non-empty string, got the string ''");
  EXPECT_EQ(problem([] { checkString("world_frame", XmlRpcValue(3), false); }),
            "~world_frame must be a non-empty string, got the integer 3");
  EXPECT_EQ(checkChoice("stale_policy", XmlRpcValue("hold"), {"fade", "hold"}), "hold");
  EXPECT_EQ(problem([] {
              checkChoice("stale_policy", XmlRpcValue("maybe"), {"fade", "hold"});
            }),
            "~stale_policy must be one of 'fade', 'hold', got the string 'maybe'");
}

TEST(Parameters, PointListAcceptsFlatNestedAndYamlStringLists) {
  Eigen::Matrix3Xd expected(3, 2);
  expected << 0, 0, 0, 0, 0, 0.02;
  const XmlRpcValue flat = list({0, 0, 0, 0, 0, 0.02});
  EXPECT_EQ(checkPointList("blade", flat, "m"), expected);
  const XmlRpcValue nested = list({list({0, 0, 0}), list({0.0, 0.0, 0.02})});
  EXPECT_EQ(checkPointList("blade", nested, "m"), expected);
  // What `rosrun surgical_sim cutting_tool _blade:="[[0,0,0],[0,0,0.02]]"` stores: a string.
  EXPECT_EQ(checkPointList("blade", XmlRpcValue("[[0,0,0],[0,0,0.02]]"), "m"), expected);
  EXPECT_EQ(checkPointList("blade", XmlRpcValue("[0, 0, 0, 0, 0, 0.02]"), "m"), expected);
}

TEST(Parameters, PointListRejectsAnythingElseNamingTheParameter) {
  for (const XmlRpcValue& bad :
       {XmlRpcValue("oops"), XmlRpcValue("[[0,0,0],[0,0"), XmlRpcValue("{a: 1}"), XmlRpcValue(0.02),
        XmlRpcValue("[]"), list({})}) {
    const std::string m = problem([&bad] { checkPointList("blade", bad, "m"); });
    EXPECT_EQ(m.rfind("~blade must be a list of points [m]", 0), 0u) << m;
  }
  EXPECT_EQ(problem([] {
              checkPointList("blade", list({0, 0, 0, 1}), "m");
            }),
            "~blade has 4 numbers; expected x y z per point");
  EXPECT_EQ(problem([] { checkPointList("blade", XmlRpcValue("[[0,0,0],[0,0]]"), "m"); }),
            "~blade point 1 is a list of 2 entries; expected [x, y, z]");
  EXPECT_EQ(problem([] { checkPointList("blade", XmlRpcValue("[[0,0,0],[0,0,oops]]"), "m"); }),
            "~blade point 1 has the string 'oops'; coordinates are numbers [m]");
}

}  // namespace
}  // namespace surgical_sim::ros_layer
