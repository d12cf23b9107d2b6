#include "surgical_sim/bench/mesh_fuzz.h"

#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace surgical_sim::bench {
namespace {

std::vector<std::string> shippedMeshes() {
  const std::string root = SURGICAL_SIM_SOURCE_DIR;
  std::vector<std::string> files = {root + "/config/meshes/liver_lobe.msh"};
  for (const char* name : {"two_tets_v22.msh", "two_tets_v41.msh", "tet10_v22.msh", "pyramid.obj",
                           "tetrahedron_ascii.stl", "tetrahedron_binary.stl"})
    files.push_back(root + "/test/data/" + name);
  return files;
}

TEST(MeshFuzz, ShippedMeshesLoadCleanly) {
  for (const std::string& file : shippedMeshes()) {
    const MeshLoadResult r = loadMeshForFuzz(file);
    EXPECT_EQ(r.outcome, MeshLoadOutcome::Loaded) << file << ": " << r.message;
  }
}

TEST(MeshFuzz, MutationIsDeterministicForASeed) {
  const std::string text =
      "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n1\n1 0.5 0 0\n$EndNodes\n";
  for (unsigned seed = 0; seed < 20; ++seed) {
    std::mt19937 a(seed), b(seed);
    const MeshMutant ma = mutateMeshFile(text, a);
    const MeshMutant mb = mutateMeshFile(text, b);
    EXPECT_EQ(ma.mutation, mb.mutation);
    EXPECT_EQ(ma.bytes, mb.bytes);
  }
}

// The corpus of the campaign's size (>= 200 files): this test is what the ASan/UBSan stage of
// scripts/test runs over the mesh readers.
TEST(MeshFuzz, TwoHundredFiftyMutantsAreLoadedValidOrRejectedNamingTheFile) {
  const std::string dir = ::testing::TempDir() + "/mesh_fuzz_test";
  std::filesystem::create_directories(dir);
  const std::vector<std::string> sources = shippedMeshes();
  int rejected = 0;
  for (int i = 0; i < 250; ++i) {
    MeshFuzzRow row = writeMeshMutant(sources, i, 14, dir);
    row.result = loadMeshForFuzz(row.file);
    SCOPED_TRACE(row.source + " / " + row.mutation + ": " + row.result.message);
    EXPECT_NE(row.result.outcome, MeshLoadOutcome::Crash);
    if (row.result.outcome == MeshLoadOutcome::RejectedWithMessage) {
      ++rejected;
      EXPECT_NE(row.result.message.find(row.file), std::string::npos);
    }
  }
  // The corruptions bite: most mutants are rejected.
  EXPECT_GE(rejected, 125);
}

}  // namespace
}  // namespace surgical_sim::bench
