// 2.1 Gauss sphere cells ("spheremeshes") and the planar enneatree over them.
//
// A unit normal maps to a cube face d1 in 0..5 (+x,-x,+y,-y,+z,-z; largest |component|, ties to
// the earlier axis) and, on that face, to two angles a1 = atan(u/|w|), a2 = atan(v/|w|) in
// [-45, 45] degrees (w the dominant component, (u,v) in the paper's order per face, Fig. 4).
// Level L splits each face into 3^L x 3^L cells of equal angle delta = 90/3^L:
// index = 3^L/2 + round(a/delta) (half away from zero), clamped to [0, 3^L-1].
// Cells nest exactly: the parent of (f,i,j) is (f,i/3,j/3).
#pragma once

#include <cstdint>

namespace gausslod {

constexpr int kMaxCellLevel = 7; // 3^7 = 2187 cells per axis; fits 12 bits

struct Cell {
	int face = 0; ///< 0..5: +x,-x,+y,-y,+z,-z
	int i = 0;    ///< index along the paper's first angle
	int j = 0;    ///< index along the second angle
	bool operator==(const Cell &o) const { return face == o.face && i == o.i && j == o.j; }
	bool operator!=(const Cell &o) const { return !(*this == o); }
};

/// 3^level: cells per axis on one cube face (the paper's MeshNum).
inline int meshNum(int level)
{
	int m = 1;
	for (int l = 0; l < level; ++l)
		m *= 3;
	return m;
}

/// A cell packed into 32 bits (face:3, i:12, j:12); kInvalidCell for "no cell".
using CellKey = uint32_t;
constexpr CellKey kInvalidCell = 0xffffffffu;
inline CellKey packCell(const Cell &c)
{
	return (CellKey(c.face) << 24) | (CellKey(c.i) << 12) | CellKey(c.j);
}
inline Cell unpackCell(CellKey k)
{
	return Cell{int(k >> 24), int((k >> 12) & 0xfff), int(k & 0xfff)};
}

/// The cell of a normal at a level (0..kMaxCellLevel). The normal need not be unit length but
/// must be finite and non-zero (returns false otherwise).
bool normalToCell(const double n[3], int level, Cell &out);

/// Parent cell (one level coarser).
inline Cell parentCell(const Cell &c) { return Cell{c.face, c.i / 3, c.j / 3}; }
inline CellKey parentKey(CellKey k) { return packCell(parentCell(unpackCell(k))); }
/// The center child (3i+1, 3j+1) of its parent?
inline bool isCenterChild(const Cell &c) { return c.i % 3 == 1 && c.j % 3 == 1; }

/// Cells of `level` touching `c` (8-neighbourhood on the sphere, across cube-face edges too).
/// Returns the count: 8, or 7 at a cube corner (4 at level 0). Symmetric by construction.
int cellNeighbours(const Cell &c, int level, Cell out[8]);

/// The unit direction at the center of a cell.
void cellCenter(const Cell &c, int level, double n[3]);

} // namespace gausslod
