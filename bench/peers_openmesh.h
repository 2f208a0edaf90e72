// OpenMesh decimater peers of bench_peers (peers_openmesh.cpp).
#pragma once

#include "bench_mesh.h"

#include <string>

/// normalDeviation false: ModQuadricT to `value` faces; true: ModQuadricT + ModNormalDeviationT
/// with a maximum deviation of `value` degrees, as far as it allows. Prints one JSON line.
int runOpenMesh(const bench::Flat &in, bool normalDeviation, double value, const std::string &out);
