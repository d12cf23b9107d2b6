#pragma once

#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <functional>
#include <vector>

namespace surgical_sim::core {

/// Triangle strip between two vertex chains of a cut's exposed surface (rest configuration).
/// Both chains run in the same direction; `ahead` lies on the left of `behind` seen from the
/// side the strip's normal points to, so the triangles (behind_i, behind_i+1, ahead_j) and
/// (behind_i, ahead_j+1, ahead_j) are counter-clockwise about that normal. The chains advance
/// together by normalised rest arc length, except that a candidate triangle of less than 0.2
/// times the other's quality (area over the sum of squared edge lengths) gives way to the other,
/// so collinear chain vertices (a chain running along a face) get no zero-area fans, and neither
/// chain's share of its segments done leads the other's by more than 0.25, so unevenly spaced
/// chains (crossings bunched up in a short stretch) make no fan either; at a shared
/// end no triangle takes all three corners from one chain (such an ear would overlap the
/// neighbouring strip). The chains may
/// share their first and/or last vertex (a lens); triangles with a repeated vertex are not emitted.
/// Without shared ends the strip has |behind| + |ahead| - 2 triangles; its boundary is the two
/// chains and the two end rungs (behind_0, ahead_0), (behind_last, ahead_last).
/// @param rest rest position [m] of a vertex id.
/// @param out triangles appended (vertex ids).
void appendStrip(const std::vector<int>& behind, const std::vector<int>& ahead,
                 const std::function<Eigen::Vector3d(int)>& rest,
                 std::vector<std::array<int, 3>>& out);

/// Intermediate rows a graded strip between chains of `dense` >= `sparse` vertices inserts, each
/// halving the dense side (halvingRow), until it has at most 2 x sparse + 2 vertices.
int gradingLevels(std::size_t dense, std::size_t sparse);

/// The row that halves the dense chain `behind` of a graded strip towards `ahead` (appendStrip's
/// conventions, rest configuration): one point for each of behind's interior vertices 2, 4, ...
/// (before its last), the fraction `f` in (0, 1) of the way from it to the point of `ahead` at
/// the same normalised rest arc length. With behind's first and last vertex it makes a chain of
/// |behind| / 2 + 1 vertices (rounded down) that shares behind's ends, so the strip from behind
/// to it is a lens and the strip from it to ahead keeps behind's end rungs: no vertex of either
/// chain gets a fan of more than a few triangles.
/// @param rest rest position [m] of a vertex id.
std::vector<Eigen::Vector3d> halvingRow(const std::vector<int>& behind,
                                        const std::vector<int>& ahead,
                                        const std::function<Eigen::Vector3d(int)>& rest, double f);

/// Number of segments of a cutting front of rest length `length` [m] after one step, from its
/// previous count: split (one segment more) while the spacing exceeds `width` w, merge (one
/// less) while it is below w / 2, never below 2 segments (the front keeps one interior transient
/// vertex). Spacings in [w/2, w] keep the count, so small blade motions add no triangles.
/// @param previous previous count, >= 2. @param width w [m] > 0.
int frontSegmentCount(double length, int previous, double width);

}  // namespace surgical_sim::core
