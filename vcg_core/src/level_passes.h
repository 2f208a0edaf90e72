// The passes that build one level's geometry from its partition, and the plain structs that
// carry state between them (level_data.h, level_scratch.h, level_steps.h). A pass takes what it
// reads as const and what it writes as non-const:
//   border_rings.cpp            2.2.2  borders, junctions, rings of every superface
//   straighten_merge.cpp        2.3    straightening (2.3.1) and vicinity merging (2.3.2)
//   superface_triangulation.cpp 2.4    re-triangulation of one superface, its retries
//   superface_checks.cpp        2.4    the checks of a pass, one registry
//   superface_projection.cpp    2.4    a superface's projection and triangulation job
//   distance_check.cpp          2.4    the distance tolerance (beyond the paper)
//   distance_bound.cpp          2.4    the distance bound of a superface (beyond the paper)
//   surface_flips.cpp           2.4    diagonals chosen by the distance (beyond the paper)
//   texture_check.cpp           2.4    the texture-stretch check (beyond the paper)
//   level_check.cpp                    the whole-level edge check
//   placement.cpp                      vertex placement once the level is valid (beyond the paper)
//   fallbacks.cpp                      fallback rounds: retry, lock, split; reuse of triangles
//   level_geometry.cpp                 the rounds of one level (level_rounds.h)
//   level_output.cpp                   its output, figures and exact superfaces
#pragma once

#include "level_data.h"    // limits, failures, borders, rings, chunk output, measures
#include "level_scratch.h" // per-thread scratch, 2D predicates, TriangleGrid, Chunks
#include "level_steps.h"   // the passes, by section
