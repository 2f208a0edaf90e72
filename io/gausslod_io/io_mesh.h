// The VCG mesh type the command-line tools read and write files with (single precision like
// MeshLab's CMeshO, per-face colour for superfaces, flags for faux edges).
#pragma once

#include <vcg/complex/complex.h>

#include <vector>

namespace gausslod {

class IoVertex;
class IoFace;
struct IoUsedTypes : public vcg::UsedTypes<vcg::Use<IoVertex>::AsVertexType, vcg::Use<IoFace>::AsFaceType> {};
class IoVertex : public vcg::Vertex<IoUsedTypes, vcg::vertex::Coord3f, vcg::vertex::Normal3f,
                                    vcg::vertex::Color4b, vcg::vertex::BitFlags> {};
class IoFace : public vcg::Face<IoUsedTypes, vcg::face::VertexRef, vcg::face::Normal3f,
                                vcg::face::Color4b, vcg::face::BitFlags> {};
class IoMesh : public vcg::tri::TriMesh<std::vector<IoVertex>, std::vector<IoFace>> {};

} // namespace gausslod
