// GroupSchedule colours chunks so that no two of a colour share a node and covers every group
// once; FeModel's energy, force, stiffness and stiffness product are bit-identical with 1 and 2
// threads for every law on Tet4 and Tet10; models start their worker threads only with their first
// parallel loop, so models whose loops never run in parallel hold none.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <iterator>
#include <memory>
#include <mutex>
#include <random>
#include <set>
#include <vector>

#include "surgical_sim/core/tissue/fe_model.h"
#include "surgical_sim/core/tissue/group_schedule.h"
#include "surgical_sim/core/tissue/mass_spring_model.h"
#include "tissue_test_util.h"

namespace surgical_sim::core {
namespace {

bool sameBits(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  return a.size() == b.size() &&
         std::memcmp(a.data(), b.data(), static_cast<size_t>(a.size()) * sizeof(double)) == 0;
}

bool sameBits(const Eigen::SparseMatrix<double>& a, const Eigen::SparseMatrix<double>& b) {
  return a.nonZeros() == b.nonZeros() &&
         std::memcmp(a.valuePtr(), b.valuePtr(),
                     static_cast<size_t>(a.nonZeros()) * sizeof(double)) == 0;
}

TEST(GroupSchedule, ChunksOfAColourShareNoNodeAndEveryGroupRunsOnce) {
  std::mt19937 rng(7);
  const TetMesh mesh = test::jitteredLattice(5, 0.01, 0.001, rng);  // 750 tets, random numbering
  const int groups = mesh.numElements();
  const GroupSchedule schedule(mesh.numNodes(), mesh.elements, 2);
  ASSERT_EQ(schedule.numChunks(),
            (groups + GroupSchedule::kGroupsPerChunk - 1) / GroupSchedule::kGroupsPerChunk);
  EXPECT_GT(schedule.numChunks(), schedule.numColours());  // some colour runs chunks in parallel
  for (int a = 0; a < schedule.numChunks(); ++a) {
    for (int b = a + 1; b < schedule.numChunks(); ++b) {
      if (schedule.colour(a) != schedule.colour(b)) continue;
      std::set<int> nodes;
      const auto chunkNodes = [&](int c, auto&& visit) {
        const int end = std::min(groups, (c + 1) * GroupSchedule::kGroupsPerChunk);
        for (int g = c * GroupSchedule::kGroupsPerChunk; g < end; ++g)
          for (int k = 0; k < 4; ++k) visit(mesh.elements(k, g));
      };
      chunkNodes(a, [&](int node) { nodes.insert(node); });
      chunkNodes(b, [&](int node) { EXPECT_EQ(nodes.count(node), 0U) << a << " " << b; });
    }
  }
  std::vector<int> runs(static_cast<size_t>(groups), 0);
  std::mutex mutex;
  schedule.forEachChunk([&](int begin, int end) {
    const std::lock_guard<std::mutex> lock(mutex);
    for (int g = begin; g < end; ++g) ++runs[static_cast<size_t>(g)];
  });
  for (int g = 0; g < groups; ++g) EXPECT_EQ(runs[static_cast<size_t>(g)], 1) << g;
  EXPECT_EQ(schedule.sumOverChunks([](int begin, int end) { return double(end - begin); }), groups);
}

TEST(GroupSchedule, RejectsAThreadCountOutOfRange) {
  GroupSchedule schedule(4, test::singleTet().elements, 1);
  EXPECT_THROW(schedule.setThreads(0), std::invalid_argument);
  EXPECT_THROW(schedule.setThreads(kMaxThreads + 1), std::invalid_argument);
}

class ThreadCountInvarianceTest : public ::testing::TestWithParam<test::LawCase> {};

TEST_P(ThreadCountInvarianceTest, OneAndTwoThreadsGiveBitIdenticalResults) {
  std::mt19937 rng(11);
  const TetMesh lattice = test::jitteredLattice(4, 0.01, 0.001, rng);  // 384 tets: 12 chunks
  const TetMesh mesh = GetParam().tet10 ? test::toTet10(lattice) : lattice;
  const Material material = test::testMaterial(0.45);
  FeModel model(mesh, material, test::makeLaw(GetParam().law, material));
  const Eigen::VectorXd x = test::perturbed(model.restPositions(), 0.002, rng);
  const Eigen::VectorXd v = test::perturbed(Eigen::VectorXd::Zero(x.size()), 1.0, rng);

  struct Results {
    double energy = 0.0;
    Eigen::VectorXd force, fused_force, product;
    Eigen::SparseMatrix<double> K[2];
  };
  const auto evaluate = [&](int threads) {
    model.setThreads(threads);
    EXPECT_EQ(model.threads(), threads);
    Results r;
    r.energy = model.energy(x);
    r.force = Eigen::VectorXd::Zero(x.size());
    model.addInternalForce(x, r.force);
    r.fused_force = Eigen::VectorXd::Zero(x.size());
    int m = 0;
    for (TangentMode mode : {TangentMode::Exact, TangentMode::ProjectedSpd}) {
      r.K[m] = model.stiffnessPattern();
      model.addInternalForceAndStiffness(x, mode, r.fused_force, r.K[m++]);
    }
    model.applyStiffness(x, TangentMode::ProjectedSpd, v, r.product);
    return r;
  };
  const Results one = evaluate(1);
  const Results two = evaluate(2);
  EXPECT_NE(one.energy, 0.0);
  EXPECT_GT(one.force.norm(), 0.0);
  EXPECT_EQ(std::memcmp(&one.energy, &two.energy, sizeof(double)), 0);
  EXPECT_TRUE(sameBits(one.force, two.force));
  EXPECT_TRUE(sameBits(one.fused_force, two.fused_force));
  EXPECT_TRUE(sameBits(one.product, two.product));
  EXPECT_TRUE(sameBits(one.K[0], two.K[0]));
  EXPECT_TRUE(sameBits(one.K[1], two.K[1]));
}

TEST(GroupSchedule, ModelsStartWorkerThreadsOnlyWithTheirFirstParallelLoop) {
  const auto processThreads = [] {  // Linux: entries of /proc/self/task
    const std::filesystem::directory_iterator tasks("/proc/self/task");
    return std::distance(std::filesystem::begin(tasks), std::filesystem::end(tasks));
  };
  std::mt19937 rng(5);
  const TetMesh mesh = test::jitteredLattice(4, 0.01, 0.001, rng);
  const Material material = test::testMaterial(0.45);
  const long before = processThreads();
  // Mass-spring loops run on the calling thread: two-thread models start nothing.
  std::vector<MassSpringModel> springs(8, MassSpringModel(mesh, material));
  for (MassSpringModel& model : springs) model.setThreads(2);
  Eigen::VectorXd f = Eigen::VectorXd::Zero(3 * mesh.numNodes());
  springs.front().addInternalForce(springs.front().restPositions(), f);
  FeModel fe(mesh, material, test::makeLaw("corotational", material));
  fe.setThreads(2);
  EXPECT_EQ(fe.threads(), 2);
  EXPECT_EQ(processThreads(), before);
  fe.addInternalForce(test::perturbed(fe.restPositions(), 0.002, rng), f);
  EXPECT_EQ(processThreads(), before + 1);  // the first parallel loop starts one worker
  fe.addInternalForce(fe.restPositions(), f);
  EXPECT_EQ(processThreads(), before + 1);
}

INSTANTIATE_TEST_SUITE_P(AllLaws, ThreadCountInvarianceTest, test::allLawCases(),
                         test::lawCaseName);

}  // namespace
}  // namespace surgical_sim::core
