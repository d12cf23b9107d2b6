#pragma once

#include <Eigen/Core>
#include <array>
#include <functional>
#include <vector>

namespace surgical_sim::core {

/// Triangle strip between two vertex chains of a cut's exposed surface (rest configuration).
/// Both chains run in the same direction; `ahead` lies on the left of `behind` seen from the
/// side the strip's normal points to, so the triangles (behind_i, behind_i+1, ahead_j) and
/// (behind_i, ahead_j+1, ahead_j) are counter-clockwise about that normal. The chains advance
/// together by normalised rest arc length, except that a candidate triangle of less than 0.2
/// times the other's quality (area over the sum of squared edge lengths) gives way to the other,
/// so collinear chain vertices (a chain running along a face) get no zero-area fans; at a shared
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

/// Number of segments of a cutting front of rest length `length` [m] after one step, from its
/// previous count: split (one segment more) while the spacing exceeds `width` w, merge (one
/// less) while it is below w / 2, never below 2 segments (the front keeps one interior transient
/// vertex). Spacings in [w/2, w] keep the count, so small blade motions add no triangles.
/// @param previous previous count, >= 2. @param width w [m] > 0.
int frontSegmentCount(double length, int previous, double width);

}  // namespace surgical_sim::core
