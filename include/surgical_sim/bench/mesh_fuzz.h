#pragma once

#include <random>
#include <string>
#include <vector>

namespace surgical_sim::bench {

/// What happened when a (possibly corrupted) mesh file was loaded.
enum class MeshLoadOutcome {
  Loaded,               ///< read, valid (requireValidMesh() for volume meshes), no warning
  RejectedWithMessage,  ///< std::runtime_error / std::invalid_argument naming the file
  WarnedRepair,         ///< read and valid, with meshWarnings() (e.g. absurd scale)
  Crash,  ///< any other exception type, an empty message or one not naming the file, or a
          ///< loaded surface breaking the reader's contract (non-finite vertex, bad index)
};

/// "loaded", "rejected_with_message", "warned_repair", "crash".
const char* toString(MeshLoadOutcome outcome);

/// Outcome of loadMeshForFuzz() and the error or warning text ("" when loaded cleanly).
struct MeshLoadResult {
  MeshLoadOutcome outcome = MeshLoadOutcome::Crash;
  std::string message;
};

/// Loads `path` with the reader its extension selects, in millimetres: ".msh" readGmsh() then
/// requireValidMesh() (its error prefixed with "path: ") and the scale warning of
/// meshWarnings(); ".obj" readObj(); ".stl" readStl(). Never throws.
MeshLoadResult loadMeshForFuzz(const std::string& path);

/// A corrupted copy of a mesh file and the name of the corruption, e.g. "number:nan",
/// "truncate_line", "bit_flip".
struct MeshMutant {
  std::string mutation;
  std::string bytes;
};

/// Derives one corrupted copy of the contents of a mesh file. Text files get one of: a numeric
/// token (count, tag, coordinate, node reference) replaced by a hostile value (NaN, Inf,
/// overflowing, huge, negative, zero, non-integer, hex, removed), coordinates scaled by 1e6, a
/// line deleted or duplicated (duplicate tags, count mismatches), two lines swapped, a section
/// header renamed (unknown section), truncation after a random line or at a section header, a
/// random byte truncation or 1-3 flipped bits. Binary files (containing a NUL byte) get a flipped
/// bit, a truncation, a NaN coordinate or an overwritten triangle count.
MeshMutant mutateMeshFile(const std::string& bytes, std::mt19937& rng);

/// One file of a mesh fuzz campaign.
struct MeshFuzzRow {
  std::string source;  ///< the uncorrupted file
  std::string file;    ///< the mutant written to disk
  std::string mutation;
  MeshLoadResult result;  ///< filled by the caller (loadMeshForFuzz())
};

/// Writes mutant `index` of a campaign: mutateMeshFile() of source index % sources.size() with
/// std::mt19937(seed + index), as "<dir>/mutant_<index><source extension>".
/// @throws std::invalid_argument for an empty source list or index < 0, std::runtime_error if
///         the source cannot be read or the mutant cannot be written.
MeshFuzzRow writeMeshMutant(const std::vector<std::string>& sources, int index, unsigned seed,
                            const std::string& dir);

}  // namespace surgical_sim::bench
