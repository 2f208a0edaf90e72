// The checks of a superface's re-triangulation (2.4 and beyond the paper), one registry: each
// check says whether a level applies it and vetoes a pass with the failure that decides what is
// tried next (Failure, level_data.h). A new check is a function in its own file and one line in
// superfaceChecks() (superface_checks.cpp).
#pragma once

#include "superface_projection.h"

namespace gausslod {
namespace detail {

/// One pass of superface s: its new triangles (o's, from firstTri) and what the checks read and
/// write: the faces' measures, and what a failure or the pass leaves for the next step.
struct SuperfacePass {
	const TriangulationInput &in;
	int32_t s;
	const Vec3 &N; ///< the superface's projection normal
	size_t firstTri;
	Scratch &w;
	ChunkOut &o;
	FaceMeasures &m;
	bool inside = false; ///< the failure is one that inside vertices can fix
	double bound = -1;   ///< the superface's distance bound, once measured (< 0: not)
};

struct SuperfaceCheck {
	const char *name;
	bool (*applies)(const LevelLimits &); ///< does a level of these limits apply it
	Failure (*check)(SuperfacePass &);    ///< Failure::None: the pass passes it
};

/// The checks in the order a pass runs them (the cheap and the preparing ones first).
const std::vector<SuperfaceCheck> &superfaceChecks();

/// Runs the checks that apply to the pass, in order; the first failure, or Failure::None.
Failure checkSuperfacePass(SuperfacePass &p);

/// The deviations deviationWithinLimit measured (deferred) into m.dev: those it would have
/// written (the same angles from the same normals: the pass's triangles are still those measured).
void writeDeviations(const TriangulationInput &in, int32_t s, Scratch &w, FaceMeasures &m);

} // namespace detail
} // namespace gausslod
