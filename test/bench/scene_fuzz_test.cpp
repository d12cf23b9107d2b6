#include "surgical_sim/bench/scene_fuzz.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace surgical_sim::bench {
namespace {

struct Scene {
  std::string path, text;
};

std::vector<Scene> shippedScenes() {
  std::vector<Scene> scenes;
  for (const char* dir : {"/config/scenes", "/config/bench"})
    for (const auto& entry :
         std::filesystem::directory_iterator(std::string(SURGICAL_SIM_SOURCE_DIR) + dir)) {
      if (entry.path().extension() != ".yaml") continue;
      std::ifstream in(entry.path());
      scenes.push_back({entry.path().string(), std::string(std::istreambuf_iterator<char>(in),
                                                           std::istreambuf_iterator<char>())});
    }
  std::sort(scenes.begin(), scenes.end(),
            [](const Scene& a, const Scene& b) { return a.path < b.path; });
  return scenes;
}

/// A rejection without a key is allowed only where there is no key to name: YAML that does not
/// parse (the message names the line) or a document that is not a map.
bool namesKeyOrSyntaxLine(const std::string& message) {
  return message.find("key '") != std::string::npos ||
         message.find("malformed YAML at line") != std::string::npos ||
         message.find("is not a YAML map") != std::string::npos;
}

TEST(SceneFuzz, HundredMutantsAreAcceptedOrRejectedNamingTheirKey) {
  const std::vector<Scene> scenes = shippedScenes();
  ASSERT_GE(scenes.size(), 5u);
  int named = 0;
  int constructed = 0;
  for (int i = 0; i < 100; ++i) {
    const Scene& scene = scenes[static_cast<std::size_t>(i) % scenes.size()];
    std::mt19937 rng(1400 + i);
    const SceneMutant mutant = mutateScene(scene.text, rng);
    // Construct only small meshes (the palpation and cutting organs, the T2 cube).
    const SceneTrialResult r =
        trySceneMutant(mutant.text, scene.path, sceneKindOf(scene.text, scene.path), 40e6);
    SCOPED_TRACE(scene.path + " / " + mutant.mutation + ": " + r.message);
    EXPECT_NE(r.outcome, SceneFuzzOutcome::Crash);
    if (r.outcome == SceneFuzzOutcome::RejectedNamingKey) ++named;
    if (r.outcome == SceneFuzzOutcome::RejectedWithoutKey) {
      EXPECT_TRUE(namesKeyOrSyntaxLine(r.message));
    }
    if (r.outcome != SceneFuzzOutcome::Accepted) {
      EXPECT_NE(r.message.find(scene.path), std::string::npos);
    }
    constructed += r.constructed;
  }
  EXPECT_GE(named, 50);
  EXPECT_GE(constructed, 5);
}

TEST(SceneFuzz, ShippedScenesAreAccepted) {
  for (const Scene& scene : shippedScenes()) {
    const SceneTrialResult r =
        trySceneMutant(scene.text, scene.path, sceneKindOf(scene.text, scene.path), 0.0);
    EXPECT_EQ(r.outcome, SceneFuzzOutcome::Accepted) << scene.path << ": " << r.message;
  }
}

}  // namespace
}  // namespace surgical_sim::bench
