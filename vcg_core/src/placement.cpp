// Beyond the paper (DESIGN 27, Params::placeVertices): vertex placement. A level's output vertices
// are input vertices, so a curved superface's triangles are chords of the surface: all on one
// side of it, their error largest between the vertices. Once the level is valid, each output
// vertex that is free to move is moved along its normal to where its triangles fit the input
// best (least squares over the input vertices and face centroids under the level's triangles,
// Jacobi iterations, each move at most half the level's tolerance); then every superface with a
// moved vertex is checked again, with every check its re-triangulation passed (normal limit,
// orientation, the surface nearest to each triangle, the distance tolerance, texture stretch,
// and its distance bound, recomputed). The vertices of a superface that fails go back to their
// input positions, and the superfaces around them are checked again, until every one passes: a
// move is kept only where all its superfaces stay within the level's guarantees. The vertices
// keep their attributes (they are still the input vertices they were).
#include "level_passes.h"

#include <algorithm>
#include <cmath>

namespace gausslod {
namespace detail {

namespace {

// Jacobi iterations of the least squares, and their damping (the moves of a vertex's neighbours
// are those of the previous iteration: a full step overshoots where they pull the same way).
constexpr int kPlaceIterations = 8;
constexpr double kPlaceDamping = 0.7;
// A move is at most this many times the level's distance tolerance (the triangles' distance to
// the surface is within it before; half of it centres them on the surface).
constexpr double kMaxMoveOfTolerance = 0.5;
// The vertices of a superface whose distance bound is below this many times the tolerance stay
// where they are: it is flat, or as good as (a move would only tilt its triangles: measured,
// moving them too cost more in the 95th percentile of the normal deviation than it gained in
// distance).
constexpr double kStillBelow = 0.25;
// A superface whose bound as accepted plus its moves stays below this many times the level's
// bound reports that sum: its own bound is not computed again (it cannot raise the level's).
constexpr double kBoundEnough = 0.9;
// A superface that fails its checks gets its vertices' moves halved this many times before they
// go back to their input positions.
constexpr uint8_t kHalvings = 2;

// One point of the input under a triangle of the level: its barycentric coordinates b1, b2 in
// the triangle (in units of 1/kUnit; b0 = 1 - b1 - b2) and its signed distance r from the
// triangle's plane; 8 bytes, since the samples are the placement's memory. Per triangle, the
// rate at which moving corner j along its normal moves the plane (normal . triangle normal; 0
// for a corner that does not move) multiplies b_j.
constexpr double kUnit = 65535.0;
struct Sample {
	uint16_t b1, b2;
	float r;
};
// The samples of a chunk of superfaces, by triangle (the chunk's triangles are a range of the
// level's: first .. first + rate.size() / 3).
struct ChunkSamples {
	size_t first = 0;
	std::vector<uint32_t> start; ///< per triangle of the chunk, its samples; + 1
	std::vector<float> rate;     ///< 3 per triangle
	std::vector<Sample> samples;
	std::vector<float> weight; ///< per sample, with Topology::sampleWeight (else empty: 1 each)
};

} // namespace

void placeVertices(const PlacementInput &pin, Chunks &chunks, Borders &b, Rings &rings,
                   FaceMeasures &m, Placement &out)
{
	const Topology &t = pin.t;
	const Partition &p = pin.p;
	const LevelTriangles &lt = pin.lt;
	const size_t nT = lt.triSf.size(), nS = p.count();
	out = Placement();
	if (!(pin.limits.maxDistance > 0) || nT == 0)
		return;
	// the vertices free to move: output vertices of a new triangle, locked by nothing, not on the
	// mesh's boundary, of no superface as close to its input as kStillBelow (a plane stays a
	// plane); each gets a slot
	std::vector<int32_t> &slot = out.slot;
	slot.assign(t.nV, -1);
	for (size_t k = 0; k < nT; ++k)
		if (lt.triBorder[k] & kNewTriangle)
			for (size_t c = 0; c < 3; ++c)
				slot[size_t(lt.tris[3 * k + c])] = 0;
	std::vector<float> accepted(nS, 0.0f); // each superface's distance bound as accepted
	for (size_t f = 0; f < t.nF; ++f)
		accepted[size_t(p.label[f])] = std::max(accepted[size_t(p.label[f])], m.gap[f]);
	for (size_t f = 0; f < t.nF; ++f)
		if (accepted[size_t(p.label[f])] < kStillBelow * pin.limits.maxDistance)
			for (size_t c = 0; c < 3; ++c)
				slot[size_t(t.T[3 * f + c])] = -1;
	for (size_t h = 0; h < 3 * t.nF; ++h) // (nor a vertex of the mesh's boundary: it stays)
		if (t.twin[h] < 0 && !t.faceDropped[h / 3])
			slot[size_t(t.T[h])] = slot[size_t(t.T[heNext(int32_t(h))])] = -1;
	int32_t slots = 0;
	for (size_t v = 0; v < t.nV; ++v)
		if (slot[v] == 0 && !t.vertexLocked[v] && !pin.extraLock[v])
			slot[v] = slots++;
		else
			slot[v] = -1;
	if (slots == 0) {
		out = Placement();
		return;
	}
	const size_t ns = size_t(slots);
	// each movable vertex's normal: the area-weighted normal of its triangles
	std::vector<Vec3> normal(ns, Vec3(0, 0, 0));
	for (size_t k = 0; k < nT; ++k) {
		const int32_t *v = &lt.tris[3 * k];
		const Vec3 n = (t.pos(v[1]) - t.pos(v[0])) ^ (t.pos(v[2]) - t.pos(v[0]));
		for (size_t c = 0; c < 3; ++c)
			if (slot[size_t(v[c])] >= 0)
				normal[size_t(slot[size_t(v[c])])] += n;
	}
	for (Vec3 &n : normal) {
		const double len = n.Norm();
		n = len > 0 ? n / len : Vec3(0, 0, 0); // (a zero normal: the vertex does not move)
	}
	// the superfaces a move may change, and their rings
	std::vector<uint8_t> involved(nS, 0);
	for (size_t k = 0; k < nT; ++k)
		for (size_t c = 0; c < 3; ++c)
			if (slot[size_t(lt.tris[3 * k + c])] >= 0)
				involved[size_t(lt.triSf[k])] = 1;
	traceRings(t, p, pin.faces, involved, chunks, b, rings);
	TriangulationInput in{t, p, pin.faces, b, rings, pin.limits, nullptr};

	// the samples of each involved superface (per chunk, in superface order): its face
	// centroids and vertices located in its triangles (a superface kept as its input faces
	// holds them exactly: one sample per face, at zero; so does, as if it held them, one made of
	// a single triangle, whose queries are never located); none where no corner moves
	std::vector<ChunkSamples> chunkSamples(chunks.out.size());
	auto triUnitNormal = [&](size_t k) {
		const int32_t *v = &lt.tris[3 * k];
		const Vec3 n = (t.pos(v[1]) - t.pos(v[0])) ^ (t.pos(v[2]) - t.pos(v[0]));
		const double len = n.Norm();
		return len > 0 ? n / len : Vec3(0, 0, 0);
	};
	chunks.forEach([&](size_t c, Scratch &w) {
		ChunkSamples &cs = chunkSamples[c];
		const int32_t s0 = chunks.start[c], s1 = chunks.start[c + 1];
		cs.first = s0 < s1 ? size_t(pin.cache[size_t(s0)].triBegin) : 0;
		const size_t last = s0 < s1 ? size_t(pin.cache[size_t(s1 - 1)].triEnd) : 0;
		const size_t ntc = last - cs.first;
		cs.start.assign(ntc + 1, 0);
		cs.rate.assign(3 * ntc, 0.0f);
		std::vector<std::pair<uint32_t, Sample>> found; // (triangle of the chunk, sample)
		std::vector<float> foundWeight;                 // (with Topology::sampleWeight)
		const bool weighted = !t.sampleWeight.empty();
		auto add = [&](size_t k, const double bc[3], double r, float weight) {
			const int32_t *v = &lt.tris[3 * k];
			if (slot[size_t(v[0])] < 0 && slot[size_t(v[1])] < 0 && slot[size_t(v[2])] < 0)
				return; // (no corner moves: nothing to fit)
			Sample smp;
			smp.b1 = uint16_t(std::lround(bc[1] * kUnit));
			smp.b2 = uint16_t(std::lround(std::min(bc[2], 1.0 - double(smp.b1) / kUnit) * kUnit));
			smp.r = float(r);
			found.emplace_back(uint32_t(k - cs.first), smp);
			if (weighted)
				foundWeight.push_back(weight);
		};
		for (int32_t s = s0; s < s1; ++s) {
			if (!involved[size_t(s)])
				continue;
			const Cached &cr = pin.cache[size_t(s)];
			const size_t first = size_t(cr.triBegin), ntri = size_t(cr.triEnd - cr.triBegin);
			bool copied = true;
			for (size_t k = first; k < first + ntri; ++k) {
				copied = copied && !(lt.triBorder[k] & kNewTriangle);
				const int32_t *v = &lt.tris[3 * k];
				const Vec3 n = triUnitNormal(k);
				for (size_t j = 0; j < 3; ++j) {
					const int32_t sj = slot[size_t(v[j])];
					cs.rate[3 * (k - cs.first) + j] =
					    sj < 0 ? 0.0f : float(normal[size_t(sj)].dot(n));
				}
			}
			if (copied || ntri == 1) {
				const double third[3] = {1.0 / 3, 1.0 / 3, 1.0 / 3};
				// (as many triangles as faces: the faces copied, in order)
				const bool asFaces =
				    weighted && int32_t(ntri) == in.faces.end(s) - in.faces.begin(s);
				for (size_t k = first; k < first + ntri; ++k)
					add(k, third, 0.0,
					    asFaces ? t.sampleWeight[size_t(
					                  in.faces.face[size_t(in.faces.begin(s)) + (k - first)])]
					            : 1.0f);
				continue;
			}
			Vec3 N;
			if (!jobFromTriangles(in, s, &lt.tris[3 * first], &lt.triBorder[first], ntri, N, w))
				continue; // (not a superface the checks could see again: its vertices stay)
			const int32_t fb = in.faces.begin(s);
			const size_t faces = size_t(in.faces.end(s) - fb);
			const size_t nq = w.job.queryTri.size();
			for (size_t q = 0; q < nq; ++q) {
				const int32_t kl = w.job.queryTri[q];
				if (kl < 0)
					continue;
				Vec3 P;
				if (q < faces) {
					const int32_t *fv = &t.T[3 * size_t(in.faces.face[size_t(fb) + q])];
					P = (t.pos(fv[0]) + t.pos(fv[1]) + t.pos(fv[2])) / 3.0;
				} else {
					P = t.pos(w.flip.queryVertex[q - faces]);
				}
				const int32_t *tv = &w.job.tris[3 * size_t(kl)];
				const double *A = &w.job.xy[2 * size_t(tv[0])], *B = &w.job.xy[2 * size_t(tv[1])],
				             *C = &w.job.xy[2 * size_t(tv[2])], *Q = &w.job.queryXY[2 * q];
				const double area = orient2(A, B, C);
				if (!(std::fabs(area) > 0))
					continue;
				// (clamped: a query just outside its triangle counts at the triangle's border)
				double bc[3] = {std::max(0.0, orient2(B, C, Q) / area),
				                std::max(0.0, orient2(C, A, Q) / area),
				                std::max(0.0, orient2(A, B, Q) / area)};
				const double sum = bc[0] + bc[1] + bc[2];
				if (!(sum > 0))
					continue;
				for (double &x : bc)
					x /= sum;
				const size_t k = first + size_t(kl);
				add(k, bc, (P - t.pos(lt.tris[3 * k])).dot(triUnitNormal(k)),
				    weighted && q < faces ? t.sampleWeight[size_t(in.faces.face[size_t(fb) + q])]
				                          : 1.0f);
			}
		}
		// by triangle (in order of discovery within one: a counting sort)
		for (const auto &f : found)
			++cs.start[f.first + 1];
		for (size_t k = 0; k < ntc; ++k)
			cs.start[k + 1] += cs.start[k];
		cs.samples.resize(found.size());
		cs.weight.resize(foundWeight.size());
		std::vector<uint32_t> fill(cs.start.begin(), cs.start.end() - 1);
		for (size_t i = 0; i < found.size(); ++i) {
			const uint32_t at = fill[found[i].first]++;
			cs.samples[at] = found[i].second;
			if (weighted)
				cs.weight[at] = foundWeight[i];
		}
	});

	// least squares for the moves d (along each vertex's normal): Jacobi iterations, in sample
	// order (the same sums for any number of threads)
	const double maxMove = kMaxMoveOfTolerance * pin.limits.maxDistance;
	std::vector<double> d(ns, 0.0), num(ns), den(ns);
	for (int it = 0; it < kPlaceIterations; ++it) {
		std::fill(num.begin(), num.end(), 0.0);
		std::fill(den.begin(), den.end(), 0.0);
		for (const ChunkSamples &cs : chunkSamples) // (in superface order)
			for (size_t kc = 0; kc + 1 < cs.start.size(); ++kc) {
				if (cs.start[kc] == cs.start[kc + 1])
					continue;
				const int32_t *v = &lt.tris[3 * (cs.first + kc)];
				const float *rate = &cs.rate[3 * kc];
				int32_t sl[3];
				double dj[3];
				for (size_t j = 0; j < 3; ++j)
					sl[j] = slot[size_t(v[j])], dj[j] = sl[j] < 0 ? 0.0 : d[size_t(sl[j])];
				for (uint32_t q = cs.start[kc]; q < cs.start[kc + 1]; ++q) {
					const Sample &smp = cs.samples[q];
					const double b1 = double(smp.b1) / kUnit, b2 = double(smp.b2) / kUnit;
					const double a[3] = {(1 - b1 - b2) * double(rate[0]), b1 * double(rate[1]),
					                     b2 * double(rate[2])};
					const double res = double(smp.r) - a[0] * dj[0] - a[1] * dj[1] - a[2] * dj[2];
					// (weighted: the input samples it stands for; 1 is exact, the same sums)
					const double wt = cs.weight.empty() ? 1.0 : double(cs.weight[q]);
					for (size_t j = 0; j < 3; ++j)
						if (sl[j] >= 0) {
							const double wa = wt * a[j];
							num[size_t(sl[j])] += wa * res, den[size_t(sl[j])] += wa * a[j];
						}
				}
			}
		for (size_t i = 0; i < ns; ++i)
			if (den[i] > 0)
				d[i] =
				    std::max(-maxMove, std::min(maxMove, d[i] + kPlaceDamping * num[i] / den[i]));
	}
	release(chunkSamples), release(num), release(den);

	// the placed positions (slots of vertices that do not move stay at their input position);
	// step[i]: the move is d / 2^step (kHalvings + 1: back at the input position)
	out.P.resize(3 * ns);
	std::vector<uint8_t> step(ns, kHalvings + 1);
	std::vector<int32_t> vertexOf(ns);
	for (size_t v = 0; v < t.nV; ++v)
		if (slot[v] >= 0)
			vertexOf[size_t(slot[v])] = int32_t(v);
	auto moveOf = [&](size_t i) { return step[i] > kHalvings ? 0.0 : std::ldexp(d[i], -step[i]); };
	auto place = [&](size_t i) {
		const size_t v = size_t(vertexOf[i]);
		const double by = moveOf(i);
		for (size_t k = 0; k < 3; ++k)
			out.P[3 * i + k] = t.P[3 * v + k] + by * normal[i][int(k)];
	};
	for (size_t i = 0; i < ns; ++i) {
		if (std::fabs(d[i]) > pin.limits.exact && normal[i].Norm() > 0)
			step[i] = 0;
		place(i);
	}

	// checks, until every superface with a moved vertex passes them; each superface's measures
	// as accepted are kept (per chunk) the first time it is checked, for when it fails or ends
	// with no vertex moved
	in.placedSlot = slot.data(), in.placedP = out.P.data();
	const float levelBound = *std::max_element(m.gap.begin(), m.gap.end());
	std::vector<uint8_t> check(nS, 0), failed(nS, 0);
	std::vector<int32_t> keptAt(nS, -1);                      // (in its chunk's store)
	std::vector<std::vector<float>> store(chunks.out.size()); // dev, gap, tex per face
	const bool tex = !m.tex.empty();
	auto measuresBack = [&](size_t c, int32_t s) {
		const float *x = &store[c][size_t(keptAt[size_t(s)])];
		for (int32_t i = in.faces.begin(s); i < in.faces.end(s); ++i, x += 3) {
			const size_t f = size_t(in.faces.face[size_t(i)]);
			m.dev[f] = x[0], m.gap[f] = x[1];
			if (tex)
				m.tex[f] = x[2];
		}
	};
	auto markAround = [&](size_t v, std::vector<uint8_t> &mark) {
		for (int32_t q = t.vfStart[v]; q < t.vfStart[v + 1]; ++q)
			mark[size_t(p.label[size_t(t.vfFace[size_t(q)])])] = 1;
	};
	for (size_t i = 0; i < ns; ++i)
		if (step[i] <= kHalvings)
			markAround(size_t(vertexOf[i]), check);
	std::vector<uint8_t> everChecked(nS, 0), halved(ns);
	for (;;) {
		std::fill(failed.begin(), failed.end(), uint8_t(0));
		chunks.forEach([&](size_t c, Scratch &w) {
			ChunkOut o;
			for (int32_t s = chunks.start[c]; s < chunks.start[c + 1]; ++s) {
				if (!check[size_t(s)])
					continue;
				const Cached &cs = pin.cache[size_t(s)];
				const size_t first = size_t(cs.triBegin), ntri = size_t(cs.triEnd - cs.triBegin);
				const int32_t fb = in.faces.begin(s), fe = in.faces.end(s);
				if (keptAt[size_t(s)] < 0) {
					keptAt[size_t(s)] = int32_t(store[c].size());
					everChecked[size_t(s)] = 1;
					for (int32_t i = fb; i < fe; ++i) {
						const size_t f = size_t(in.faces.face[size_t(i)]);
						store[c].push_back(m.dev[f]);
						store[c].push_back(m.gap[f]);
						store[c].push_back(tex ? m.tex[f] : 0.0f);
					}
				}
				for (int32_t i = fb; i < fe; ++i) {
					const size_t f = size_t(in.faces.face[size_t(i)]);
					m.dev[f] = -1.0f, m.gap[f] = 0.0f;
					if (tex)
						m.tex[f] = 0.0f;
				}
				// (the bound as accepted, plus the largest move of its vertices from there, bounds
				// it too)
				const float before = accepted[size_t(s)];
				double moves = 0;
				for (size_t k = first; k < first + ntri; ++k)
					for (size_t j = 0; j < 3; ++j)
						moves = std::max(moves, in.moved(lt.tris[3 * k + j]));
				w.boundCap = double(before) * (1 + 1e-6) + moves;
				w.boundEnough = kBoundEnough * double(levelBound);
				Vec3 N;
				double bound = 0;
				o.truncate(0);
				bool ok = jobFromTriangles(in, s, &lt.tris[3 * first], &lt.triBorder[first], ntri,
				                           N, w) &&
				          checkTriangles(in, s, N, w, o, m, bound) == Failure::None;
				w.boundCap = HUGE_VAL, w.boundEnough = 0;
				if (ok) { // (the level's bound does not grow)
					float after = 0;
					for (int32_t i = fb; i < fe; ++i)
						after = std::max(after, m.gap[size_t(in.faces.face[size_t(i)])]);
					ok = after <= std::max(before, levelBound);
				}
				if (!ok) {
					failed[size_t(s)] = 1;
					measuresBack(c, s);
				}
			}
		});
		// the failed superfaces' vertices move half as far (then go back); the superfaces around
		// them (the failed ones too) are checked again
		std::fill(check.begin(), check.end(), uint8_t(0));
		bool again = false;
		std::fill(halved.begin(), halved.end(), uint8_t(0));
		for (size_t s = 0; s < nS; ++s) {
			if (!failed[s])
				continue;
			const Cached &cs = pin.cache[s];
			for (size_t k = size_t(cs.triBegin); k < size_t(cs.triEnd); ++k)
				for (size_t j = 0; j < 3; ++j) {
					const size_t v = size_t(lt.tris[3 * k + j]);
					const int32_t i = slot[v];
					if (i < 0 || step[size_t(i)] > kHalvings || halved[size_t(i)])
						continue;
					halved[size_t(i)] = 1; // (once per round, however many triangles hold it)
					++step[size_t(i)];
					place(size_t(i));
					markAround(v, check);
					again = true;
				}
		}
		if (!again) // (each round that goes on halves or takes back a move: it ends)
			break;
	}
	// a superface checked with moved vertices that has none left is as accepted, measures too
	std::vector<uint8_t> anyMoved(nS, 0);
	for (size_t i = 0; i < ns; ++i)
		if (step[i] <= kHalvings)
			markAround(size_t(vertexOf[i]), anyMoved);
	for (size_t c = 0; c < chunks.out.size(); ++c)
		for (int32_t s = chunks.start[c]; s < chunks.start[c + 1]; ++s)
			if (everChecked[size_t(s)] && !anyMoved[size_t(s)])
				measuresBack(c, s);
	for (size_t i = 0; i < ns; ++i)
		if (step[i] <= kHalvings) {
			++out.moved;
			out.maxMove = std::max(out.maxMove, std::fabs(moveOf(i)));
		}
	if (out.moved == 0)
		out = Placement();
}

} // namespace detail
} // namespace gausslod
