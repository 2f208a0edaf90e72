// Internal data of the GaussLOD engine: flat arrays indexed by vertex, face and half-edge
// (half-edge h = 3*face + k goes from corner k to corner (k+1)%3 of its face). This header only
// gathers the engine's headers, one per concern.
#pragma once

#include "buckets.h"        // counting sorts (CSR), release
#include "coplanar.h"       // reduceCoplanar
#include "face_grid.h"      // FaceGrid
#include "geometry.h"       // Vec3, half-edges, distances, angles, cellOfNormal
#include "hierarchy.h"      // 2.5 coarserPartition, mergeAcrossCells, sameCoarserPartition
#include "level_geometry.h" // 2.2.2-2.4 buildLevelGeometry, SplitCost, ExactCarry
#include "partition.h"      // 2.2.1 Partition, finestPartition
#include "thread_pool.h"    // threadCount, onWorkers, parallelRanges
#include "topology.h"       // Topology, FaceMeasure, weldVertices, buildTopology
#include "triangulation.h"  // 2.4 TriangulationJob, triangulateRings
