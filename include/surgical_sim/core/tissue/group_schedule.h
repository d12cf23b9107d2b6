#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <memory>
#include <vector>

#include "surgical_sim/core/common/thread_pool.h"

namespace surgical_sim::core {

/// A thread-count-independent parallel order for loops over groups (elements, springs) that
/// scatter-add into node data: the groups are cut into chunks of consecutive groups, and the
/// chunks are coloured greedily (in chunk order) so that no two chunks of one colour share a node.
/// A loop runs the colours one after the other, the chunks of a colour in parallel, the groups of
/// a chunk in order; every node's sum therefore adds its contributions in the same order (colour,
/// then group) whatever the thread count, and results are bit-identical with 1 or more threads.
class GroupSchedule {
 public:
  /// Groups per chunk [-]: enough work per task to hide the hand-over, small enough for a few
  /// chunks per colour on organ meshes.
  static constexpr int kGroupsPerChunk = 32;

  GroupSchedule() = default;
  /// @param num_nodes n; @param groups node indices, shape k x g, in [0, n).
  /// @param threads threads of the loops, in [1, kMaxThreads] (see setThreads)
  GroupSchedule(int num_nodes, const Eigen::MatrixXi& groups, int threads);

  /// Threads the loops use (1: the calling thread alone, no pool). The worker threads start with
  /// the first loop that has a colour of more than one chunk (LazyThreadPool).
  /// @throws std::invalid_argument naming "threads" outside [1, kMaxThreads].
  void setThreads(int threads);
  int threads() const { return pool_ ? pool_->threads() : 1; }
  int numColours() const { return static_cast<int>(colour_offsets_.size()) - 1; }
  int numChunks() const { return static_cast<int>(chunks_.size()); }
  /// Colour of chunk c (groups [c kGroupsPerChunk, min(g, (c + 1) kGroupsPerChunk))).
  int colour(int chunk) const { return colour_[static_cast<size_t>(chunk)]; }

  /// Calls body(begin, end) for every chunk [begin, end) of groups, in the order of the class
  /// comment; chunks of one colour run concurrently, so body may write any data of its groups'
  /// nodes but nothing shared with other chunks. Allocation-free.
  template <typename Body>
  void forEachChunk(Body&& body) const {
    forEachChunkIndex([&](int chunk) { body(chunkBegin(chunk), chunkEnd(chunk)); });
  }
  /// Sum of body(begin, end) over the chunks, added in chunk order (independent of the threads).
  /// Allocation-free after the first call on a thread.
  template <typename Body>
  double sumOverChunks(Body&& body) const {
    double* partial = partialSums();
    forEachChunkIndex(
        [&](int chunk) { partial[chunk] = body(chunkBegin(chunk), chunkEnd(chunk)); });
    return sumInOrder(partial);
  }

 private:
  int chunkBegin(int chunk) const { return chunk * kGroupsPerChunk; }
  int chunkEnd(int chunk) const { return std::min(num_groups_, (chunk + 1) * kGroupsPerChunk); }
  /// Runs body(chunk) for the chunks of each colour in turn, those of a colour in parallel (the
  /// pool's task captures two pointers: no allocation in std::function).
  template <typename Body>
  void forEachChunkIndex(Body&& body) const {
    for (size_t k = 0; k + 1 < colour_offsets_.size(); ++k) {
      const int* first = chunks_.data() + colour_offsets_[k];
      const int count = colour_offsets_[k + 1] - colour_offsets_[k];
      if (pool_) {
        pool_->run(count, [first, &body](int i) { body(first[i]); });
      } else {
        for (int i = 0; i < count; ++i) body(first[i]);
      }
    }
  }
  /// Per-chunk work space of sumOverChunks (thread-local storage of the calling thread).
  double* partialSums() const;
  double sumInOrder(const double* partial) const;

  int num_groups_ = 0;
  std::vector<int> colour_;               ///< per chunk
  std::vector<int> chunks_;               ///< chunk indices sorted by colour (then index)
  std::vector<int> colour_offsets_;       ///< chunks_ of colour c: [colour_offsets_[c], [c + 1])
  std::shared_ptr<LazyThreadPool> pool_;  ///< null for one thread; shared by copies
};

}  // namespace surgical_sim::core
