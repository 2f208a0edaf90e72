// The VCG mesh types the command-line tools read and write files with (single precision like
// MeshLab's CMeshO). IoMesh: positions, faces, per-face colour for superfaces, flags for faux
// edges (the lean path of files without attributes). IoAttrMesh: also the attributes a level
// carries from its input (per-vertex colour, quality, texture coordinates, normal; per-wedge
// texture coordinates with their texture index; per-face colour), used only for files that
// have them.
#pragma once

#include <vcg/complex/complex.h>

#include <vector>

namespace gausslod {

class IoVertex;
class IoFace;
struct IoUsedTypes
    : public vcg::UsedTypes<vcg::Use<IoVertex>::AsVertexType, vcg::Use<IoFace>::AsFaceType> {};
class IoVertex : public vcg::Vertex<IoUsedTypes, vcg::vertex::Coord3f, vcg::vertex::Normal3f,
                                    vcg::vertex::Color4b, vcg::vertex::BitFlags> {};
class IoFace : public vcg::Face<IoUsedTypes, vcg::face::VertexRef, vcg::face::Normal3f,
                                vcg::face::Color4b, vcg::face::BitFlags> {};
// (VCG's TriMesh() leaves its attribute counter `attrn` unset, ClearAttributes() sets it; each
// attribute handle compares its number with it: set here)
class IoMesh : public vcg::tri::TriMesh<std::vector<IoVertex>, std::vector<IoFace>> {
public:
	IoMesh() { attrn = 0; }
};

class IoAttrVertex;
class IoAttrFace;
struct IoAttrUsedTypes : public vcg::UsedTypes<vcg::Use<IoAttrVertex>::AsVertexType,
                                               vcg::Use<IoAttrFace>::AsFaceType> {};
class IoAttrVertex
    : public vcg::Vertex<IoAttrUsedTypes, vcg::vertex::Coord3f, vcg::vertex::Normal3f,
                         vcg::vertex::Color4b, vcg::vertex::Qualityf, vcg::vertex::TexCoord2f,
                         vcg::vertex::BitFlags> {};
class IoAttrFace
    : public vcg::Face<IoAttrUsedTypes, vcg::face::VertexRef, vcg::face::Normal3f,
                       vcg::face::Color4b, vcg::face::WedgeTexCoord2f, vcg::face::BitFlags> {};
class IoAttrMesh : public vcg::tri::TriMesh<std::vector<IoAttrVertex>, std::vector<IoAttrFace>> {
public:
	IoAttrMesh() { attrn = 0; }
};

} // namespace gausslod
