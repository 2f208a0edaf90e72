// 2.1 Scheme for hierarchically subdividing the Gauss sphere (paper Fig. 2-4).
#include "sphere_cells.h"

#include <cmath>

namespace gausslod {

namespace {

constexpr double kPi = 3.14159265358979323846;

// Per cube face: dominant axis, and the axes of the paper's Angle1 (u) and Angle2 (v) (Fig. 4).
struct FaceAxes {
	int w, u, v;
	double sign;
};
constexpr FaceAxes kAxes[6] = {{0, 2, 1, +1}, {0, 2, 1, -1}, {1, 0, 2, +1},
                               {1, 0, 2, -1}, {2, 1, 0, +1}, {2, 1, 0, -1}};

double deltaRad(int level) { return (kPi / 2) / meshNum(level); }

int angleToIndex(double a, int level)
{
	const int m = meshNum(level);
	const double t = a / deltaRad(level);
	// round half away from zero, then clamp: the paper's formula overflows at exactly +-45 deg
	const long r = long(t >= 0 ? std::floor(t + 0.5) : -std::floor(-t + 0.5));
	long d = long(m / 2) + r;
	if (d < 0)
		d = 0;
	if (d > m - 1)
		d = m - 1;
	return int(d);
}

double indexToAngle(int idx, int level) { return (idx - meshNum(level) / 2) * deltaRad(level); }

bool anglesToCell(int face, double a1, double a2, int level, Cell &out)
{
	double n[3];
	const FaceAxes &ax = kAxes[face];
	n[ax.w] = ax.sign;
	n[ax.u] = std::tan(a1);
	n[ax.v] = std::tan(a2);
	return normalToCell(n, level, out);
}

} // namespace

bool normalToCell(const double n[3], int level, Cell &out)
{
	if (!(std::isfinite(n[0]) && std::isfinite(n[1]) && std::isfinite(n[2])) || level < 0 ||
	    level > kMaxCellLevel)
		return false;
	const double ax = std::fabs(n[0]), ay = std::fabs(n[1]), az = std::fabs(n[2]);
	int dom;
	if (ax >= ay && ax >= az)
		dom = 0;
	else if (ay >= az)
		dom = 1;
	else
		dom = 2;
	const double w = n[dom];
	if (w == 0)
		return false;
	const int face = 2 * dom + (w > 0 ? 0 : 1);
	const FaceAxes &fa = kAxes[face];
	const double aw = std::fabs(w);
	out.face = face;
	out.i = angleToIndex(std::atan(n[fa.u] / aw), level);
	out.j = angleToIndex(std::atan(n[fa.v] / aw), level);
	return true;
}

void cellCenter(const Cell &c, int level, double n[3])
{
	const FaceAxes &ax = kAxes[c.face];
	n[ax.w] = ax.sign;
	n[ax.u] = std::tan(indexToAngle(c.i, level));
	n[ax.v] = std::tan(indexToAngle(c.j, level));
	const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
	for (int k = 0; k < 3; ++k)
		n[k] /= len;
}

int cellNeighbours(const Cell &c, int level, Cell out[8])
{
	const int m = meshNum(level);
	// The equi-angular map divides a cube edge identically on both faces, so a step across an
	// edge lands on the cell of the other face that touches this one: take a point just across
	// the edge (1% of a cell beyond 45 deg) at the along-edge center of the target column/row.
	const double beyond = (kPi / 4) + 0.01 * deltaRad(level);
	int count = 0;
	for (int di = -1; di <= 1; ++di) {
		for (int dj = -1; dj <= 1; ++dj) {
			if (di == 0 && dj == 0)
				continue;
			const int ni = c.i + di, nj = c.j + dj;
			const bool inI = ni >= 0 && ni < m, inJ = nj >= 0 && nj < m;
			Cell nb;
			if (inI && inJ) {
				nb = Cell{c.face, ni, nj};
			} else if (inI != inJ) {
				const double a1 = inI ? indexToAngle(ni, level) : (ni < 0 ? -beyond : beyond);
				const double a2 = inJ ? indexToAngle(nj, level) : (nj < 0 ? -beyond : beyond);
				if (!anglesToCell(c.face, a1, a2, level, nb))
					continue;
			} else {
				continue; // diagonal step off a cube corner: no such cell
			}
			bool dup = nb == c;
			for (int k = 0; k < count && !dup; ++k)
				dup = out[k] == nb;
			if (!dup)
				out[count++] = nb;
		}
	}
	return count;
}

} // namespace gausslod
