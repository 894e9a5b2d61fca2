// Least-squares conformal maps (Levy et al. 2002) through CGAL: a group of faces laid flat, as the
// atlas flattens its charts and surface quilting its work patches (Zhou 2005 §III-B).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "mesh/triangle_mesh.h"

namespace mesocap {

// Per face of `faces`, its corners' (u, v) at LSCM's own scale, turned so that the faces keep
// their winding (counter-clockwise seen from their normal side); empty when the faces are not one
// topological disk or the flattening folds faces of more than `folded_area_share` of their area
// (slivers of a marched surface can fold unseen; an atlas' charts must not fold at all).
std::vector<std::array<Eigen::Vector2d, 3>> FlattenByLscm(const TriangleMesh& mesh, const std::vector<int32_t>& faces,
                                                          double folded_area_share = 0);

}  // namespace mesocap
