#include "surgical_sim/core/tissue/group_schedule.h"

#include <cstdint>

#include "surgical_sim/core/common/validate.h"

namespace surgical_sim::core {
namespace {

/// Colours tracked per node in a bit mask; a chunk that finds all taken gets a colour of its own.
constexpr int kMaskColours = 64;

}  // namespace

GroupSchedule::GroupSchedule(int num_nodes, const Eigen::MatrixXi& groups, int threads)
    : num_groups_(static_cast<int>(groups.cols())) {
  const int num_chunks = (num_groups_ + kGroupsPerChunk - 1) / kGroupsPerChunk;
  // Greedy colouring in chunk order: the lowest colour no earlier chunk at one of its nodes has.
  std::vector<std::uint64_t> node_colours(static_cast<size_t>(num_nodes), 0);
  std::vector<int>& colour = colour_;
  colour.resize(static_cast<size_t>(num_chunks));
  int num_colours = 0;
  for (int c = 0; c < num_chunks; ++c) {
    std::uint64_t taken = 0;
    for (int g = chunkBegin(c); g < chunkEnd(c); ++g) {
      for (Eigen::Index a = 0; a < groups.rows(); ++a)
        taken |= node_colours[static_cast<size_t>(groups(a, g))];
    }
    int chosen = 0;
    while (chosen < kMaskColours && (taken >> chosen & 1U) != 0) ++chosen;
    if (chosen < kMaskColours) {
      for (int g = chunkBegin(c); g < chunkEnd(c); ++g) {
        for (Eigen::Index a = 0; a < groups.rows(); ++a)
          node_colours[static_cast<size_t>(groups(a, g))] |= std::uint64_t{1} << chosen;
      }
    } else {
      chosen = kMaskColours + c;  // alone in its colour, after every masked colour
    }
    colour[static_cast<size_t>(c)] = chosen;
    num_colours = std::max(num_colours, chosen + 1);
  }
  // Chunks sorted by colour, in chunk order within a colour (counting sort).
  colour_offsets_.assign(static_cast<size_t>(num_colours + 1), 0);
  for (int c = 0; c < num_chunks; ++c) ++colour_offsets_[static_cast<size_t>(colour[c] + 1)];
  for (int k = 0; k < num_colours; ++k) colour_offsets_[k + 1] += colour_offsets_[k];
  std::vector<int> next(colour_offsets_.begin(), colour_offsets_.end() - 1);
  chunks_.resize(static_cast<size_t>(num_chunks));
  for (int c = 0; c < num_chunks; ++c) {
    chunks_[static_cast<size_t>(next[static_cast<size_t>(colour[c])]++)] = c;
  }
  setThreads(threads);
}

void GroupSchedule::setThreads(int threads) {
  requireInRange("threads", threads, 1, kMaxThreads, "");
  if (threads == 1) {
    pool_.reset();
  } else if (!pool_ || pool_->threads() != threads) {
    pool_ = std::make_shared<LazyThreadPool>(threads);
  }
}

double* GroupSchedule::partialSums() const {
  thread_local std::vector<double> partial;
  if (partial.size() < chunks_.size()) partial.resize(chunks_.size());
  return partial.data();
}

double GroupSchedule::sumInOrder(const double* partial) const {
  double sum = 0.0;
  for (int c = 0; c < numChunks(); ++c) sum += partial[c];
  return sum;
}

}  // namespace surgical_sim::core
