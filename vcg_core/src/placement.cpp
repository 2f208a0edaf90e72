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

// The samples found in a chunk, before they are sorted by triangle.
struct FoundSamples {
	std::vector<std::pair<uint32_t, Sample>> at; ///< (triangle of the chunk, sample)
	std::vector<float> weight;                   ///< (with Topology::sampleWeight)
};

// One run of placeVertices: its steps share the slots, normals, moves and checks' state.
class VertexPlacer {
public:
	VertexPlacer(const PlacementInput &pin, Chunks &chunks, Borders &b, Rings &rings,
	             FaceMeasures &m, Placement &out)
	    : pin_(pin), t_(pin.t), p_(pin.p), lt_(pin.lt), chunks_(chunks), b_(b), rings_(rings),
	      m_(m), out_(out), slot_(out.slot), nT_(pin.lt.triSf.size()), nS_(pin.p.count()),
	      weighted_(!pin.t.sampleWeight.empty()), in_{pin.t, pin.p,      pin.faces, b,
	                                                  rings, pin.limits, nullptr}
	{
	}
	void run();

private:
	const PlacementInput &pin_;
	const Topology &t_;
	const Partition &p_;
	const LevelTriangles &lt_;
	Chunks &chunks_;
	Borders &b_;
	Rings &rings_;
	FaceMeasures &m_;
	Placement &out_;
	std::vector<int32_t> &slot_; ///< out_.slot
	const size_t nT_, nS_;
	const bool weighted_; ///< the samples have weights (Topology::sampleWeight)
	TriangulationInput in_;
	size_t ns_ = 0;                 ///< slots
	std::vector<float> accepted_;   ///< per superface, its distance bound as accepted
	std::vector<Vec3> normal_;      ///< per slot
	std::vector<uint8_t> involved_; ///< per superface: a move may change it
	std::vector<ChunkSamples> chunkSamples_;
	std::vector<double> d_;         ///< per slot, its move along its normal
	std::vector<uint8_t> step_;     ///< per slot: the move is d / 2^step (kHalvings + 1: none)
	std::vector<int32_t> vertexOf_; ///< per slot
	// the checks
	float levelBound_ = 0;
	bool tex_ = false;
	std::vector<uint8_t> check_, failed_, everChecked_, halved_;
	std::vector<int32_t> keptAt_;           ///< per superface, in its chunk's store (-1)
	std::vector<std::vector<float>> store_; ///< per chunk: dev, gap, tex per face as accepted

	bool chooseSlots();
	void vertexNormals();
	void traceInvolved();
	Vec3 triUnitNormal(size_t k) const;
	void sampleChunk(size_t c, Scratch &w);
	bool triangleRates(ChunkSamples &cs, size_t first, size_t ntri);
	void addSample(ChunkSamples &cs, FoundSamples &found, size_t k, const double bc[3], double r,
	               float weight) const;
	void sampleLocated(ChunkSamples &cs, FoundSamples &found, int32_t s, size_t first, size_t ntri,
	                   Scratch &w);
	void solveMoves();
	double moveOf(size_t i) const
	{
		return step_[i] > kHalvings ? 0.0 : std::ldexp(d_[i], -step_[i]);
	}
	void place(size_t i);
	void placeAll();
	void measuresBack(size_t c, int32_t s);
	void markAround(size_t v, std::vector<uint8_t> &mark) const;
	void checkSuperface(size_t c, int32_t s, Scratch &w, ChunkOut &o);
	bool halveFailed();
	void keepMoved();
};

// The vertices free to move: output vertices of a new triangle, locked by nothing, not on the
// mesh's boundary, of no superface as close to its input as kStillBelow (a plane stays a plane);
// each gets a slot. False if none does.
bool VertexPlacer::chooseSlots()
{
	const Topology &t = t_;
	const Partition &p = p_;
	const LevelTriangles &lt = lt_;
	std::vector<int32_t> &slot = slot_;
	slot.assign(t.nV, -1);
	for (size_t k = 0; k < nT_; ++k)
		if (lt.triBorder[k] & kNewTriangle)
			for (size_t c = 0; c < 3; ++c)
				slot[size_t(lt.tris[3 * k + c])] = 0;
	accepted_.assign(nS_, 0.0f);
	for (size_t f = 0; f < t.nF; ++f)
		accepted_[size_t(p.label[f])] = std::max(accepted_[size_t(p.label[f])], m_.gap[f]);
	for (size_t f = 0; f < t.nF; ++f)
		if (accepted_[size_t(p.label[f])] < kStillBelow * pin_.limits.maxDistance)
			for (size_t c = 0; c < 3; ++c)
				slot[size_t(t.T[3 * f + c])] = -1;
	for (size_t h = 0; h < 3 * t.nF; ++h) // (nor a vertex of the mesh's boundary: it stays)
		if (t.twin[h] < 0 && !t.faceDropped[h / 3])
			slot[size_t(t.T[h])] = slot[size_t(t.T[heNext(int32_t(h))])] = -1;
	int32_t slots = 0;
	for (size_t v = 0; v < t.nV; ++v)
		if (slot[v] == 0 && !t.vertexLocked[v] && !pin_.extraLock[v])
			slot[v] = slots++;
		else
			slot[v] = -1;
	ns_ = size_t(slots);
	return slots > 0;
}

// Each movable vertex's normal: the area-weighted normal of its triangles.
void VertexPlacer::vertexNormals()
{
	normal_.assign(ns_, Vec3(0, 0, 0));
	for (size_t k = 0; k < nT_; ++k) {
		const int32_t *v = &lt_.tris[3 * k];
		const Vec3 n = (t_.pos(v[1]) - t_.pos(v[0])) ^ (t_.pos(v[2]) - t_.pos(v[0]));
		for (size_t c = 0; c < 3; ++c)
			if (slot_[size_t(v[c])] >= 0)
				normal_[size_t(slot_[size_t(v[c])])] += n;
	}
	for (Vec3 &n : normal_) {
		const double len = n.Norm();
		n = len > 0 ? n / len : Vec3(0, 0, 0); // (a zero normal: the vertex does not move)
	}
}

// The superfaces a move may change, and their rings.
void VertexPlacer::traceInvolved()
{
	involved_.assign(nS_, 0);
	for (size_t k = 0; k < nT_; ++k)
		for (size_t c = 0; c < 3; ++c)
			if (slot_[size_t(lt_.tris[3 * k + c])] >= 0)
				involved_[size_t(lt_.triSf[k])] = 1;
	traceRings(t_, p_, pin_.faces, involved_, chunks_, b_, rings_);
}

Vec3 VertexPlacer::triUnitNormal(size_t k) const
{
	const int32_t *v = &lt_.tris[3 * k];
	const Vec3 n = (t_.pos(v[1]) - t_.pos(v[0])) ^ (t_.pos(v[2]) - t_.pos(v[0]));
	const double len = n.Norm();
	return len > 0 ? n / len : Vec3(0, 0, 0);
}

// A sample of triangle k at barycentric coordinates bc, r from its plane; none if no corner of
// the triangle moves (nothing to fit).
void VertexPlacer::addSample(ChunkSamples &cs, FoundSamples &found, size_t k, const double bc[3],
                             double r, float weight) const
{
	const int32_t *v = &lt_.tris[3 * k];
	if (slot_[size_t(v[0])] < 0 && slot_[size_t(v[1])] < 0 && slot_[size_t(v[2])] < 0)
		return; // (no corner moves: nothing to fit)
	Sample smp;
	smp.b1 = uint16_t(std::lround(bc[1] * kUnit));
	smp.b2 = uint16_t(std::lround(std::min(bc[2], 1.0 - double(smp.b1) / kUnit) * kUnit));
	smp.r = float(r);
	found.at.emplace_back(uint32_t(k - cs.first), smp);
	if (weighted_)
		found.weight.push_back(weight);
}

// The rates of the triangles [first, first + ntri) (see Sample); true if they are all copied
// (none is a new triangle).
bool VertexPlacer::triangleRates(ChunkSamples &cs, size_t first, size_t ntri)
{
	bool copied = true;
	for (size_t k = first; k < first + ntri; ++k) {
		copied = copied && !(lt_.triBorder[k] & kNewTriangle);
		const int32_t *v = &lt_.tris[3 * k];
		const Vec3 n = triUnitNormal(k);
		for (size_t j = 0; j < 3; ++j) {
			const int32_t sj = slot_[size_t(v[j])];
			cs.rate[3 * (k - cs.first) + j] = sj < 0 ? 0.0f : float(normal_[size_t(sj)].dot(n));
		}
	}
	return copied;
}

// The samples of superface s whose triangles [first, first + ntri) are new: its face centroids
// and vertices located in them (none if the checks could not see it again: its vertices stay).
void VertexPlacer::sampleLocated(ChunkSamples &cs, FoundSamples &found, int32_t s, size_t first,
                                 size_t ntri, Scratch &w)
{
	const Topology &t = t_;
	Vec3 N;
	if (!jobFromTriangles(in_, s, &lt_.tris[3 * first], &lt_.triBorder[first], ntri, N, w))
		return; // (not a superface the checks could see again: its vertices stay)
	const int32_t fb = in_.faces.begin(s);
	const size_t faces = size_t(in_.faces.end(s) - fb);
	const size_t nq = w.job.queryTri.size();
	for (size_t q = 0; q < nq; ++q) {
		const int32_t kl = w.job.queryTri[q];
		if (kl < 0)
			continue;
		Vec3 P;
		if (q < faces) {
			const int32_t *fv = &t.T[3 * size_t(in_.faces.face[size_t(fb) + q])];
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
		addSample(cs, found, k, bc, (P - t.pos(lt_.tris[3 * k])).dot(triUnitNormal(k)),
		          weighted_ && q < faces ? t.sampleWeight[size_t(in_.faces.face[size_t(fb) + q])]
		                                 : 1.0f);
	}
}

// The samples found, by triangle (in order of discovery within one: a counting sort).
void sortSamples(const FoundSamples &found, bool weighted, ChunkSamples &cs)
{
	const size_t ntc = cs.start.size() - 1;
	for (const auto &f : found.at)
		++cs.start[f.first + 1];
	for (size_t k = 0; k < ntc; ++k)
		cs.start[k + 1] += cs.start[k];
	cs.samples.resize(found.at.size());
	cs.weight.resize(found.weight.size());
	std::vector<uint32_t> fill(cs.start.begin(), cs.start.end() - 1);
	for (size_t i = 0; i < found.at.size(); ++i) {
		const uint32_t at = fill[found.at[i].first]++;
		cs.samples[at] = found.at[i].second;
		if (weighted)
			cs.weight[at] = found.weight[i];
	}
}

// The samples of each involved superface of chunk c (in superface order): its face centroids
// and vertices located in its triangles (a superface kept as its input faces holds them exactly:
// one sample per face, at zero; so does, as if it held them, one made of a single triangle, whose
// queries are never located); none where no corner moves.
void VertexPlacer::sampleChunk(size_t c, Scratch &w)
{
	ChunkSamples &cs = chunkSamples_[c];
	const int32_t s0 = chunks_.start[c], s1 = chunks_.start[c + 1];
	cs.first = s0 < s1 ? size_t(pin_.cache[size_t(s0)].triBegin) : 0;
	const size_t last = s0 < s1 ? size_t(pin_.cache[size_t(s1 - 1)].triEnd) : 0;
	const size_t ntc = last - cs.first;
	cs.start.assign(ntc + 1, 0);
	cs.rate.assign(3 * ntc, 0.0f);
	FoundSamples found;
	for (int32_t s = s0; s < s1; ++s) {
		if (!involved_[size_t(s)])
			continue;
		const Cached &cr = pin_.cache[size_t(s)];
		const size_t first = size_t(cr.triBegin), ntri = size_t(cr.triEnd - cr.triBegin);
		const bool copied = triangleRates(cs, first, ntri);
		if (!copied && ntri != 1) {
			sampleLocated(cs, found, s, first, ntri, w);
			continue;
		}
		const double third[3] = {1.0 / 3, 1.0 / 3, 1.0 / 3};
		// (as many triangles as faces: the faces copied, in order)
		const bool asFaces = weighted_ && int32_t(ntri) == in_.faces.end(s) - in_.faces.begin(s);
		for (size_t k = first; k < first + ntri; ++k)
			addSample(cs, found, k, third, 0.0,
			          asFaces ? t_.sampleWeight[size_t(
			                        in_.faces.face[size_t(in_.faces.begin(s)) + (k - first)])]
			                  : 1.0f);
	}
	sortSamples(found, weighted_, cs);
}

// Least squares for the moves d (along each vertex's normal): Jacobi iterations, in sample order
// (the same sums for any number of threads).
void VertexPlacer::solveMoves()
{
	const double maxMove = kMaxMoveOfTolerance * pin_.limits.maxDistance;
	std::vector<double> &d = d_;
	d.assign(ns_, 0.0);
	std::vector<double> num(ns_), den(ns_);
	for (int it = 0; it < kPlaceIterations; ++it) {
		std::fill(num.begin(), num.end(), 0.0);
		std::fill(den.begin(), den.end(), 0.0);
		for (const ChunkSamples &cs : chunkSamples_) // (in superface order)
			for (size_t kc = 0; kc + 1 < cs.start.size(); ++kc) {
				if (cs.start[kc] == cs.start[kc + 1])
					continue;
				const int32_t *v = &lt_.tris[3 * (cs.first + kc)];
				const float *rate = &cs.rate[3 * kc];
				int32_t sl[3];
				double dj[3];
				for (size_t j = 0; j < 3; ++j)
					sl[j] = slot_[size_t(v[j])], dj[j] = sl[j] < 0 ? 0.0 : d[size_t(sl[j])];
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
		for (size_t i = 0; i < ns_; ++i)
			if (den[i] > 0)
				d[i] =
				    std::max(-maxMove, std::min(maxMove, d[i] + kPlaceDamping * num[i] / den[i]));
	}
}

void VertexPlacer::place(size_t i)
{
	const size_t v = size_t(vertexOf_[i]);
	const double by = moveOf(i);
	for (size_t k = 0; k < 3; ++k)
		out_.P[3 * i + k] = t_.P[3 * v + k] + by * normal_[i][int(k)];
}

// The placed positions (slots of vertices that do not move stay at their input position).
void VertexPlacer::placeAll()
{
	out_.P.resize(3 * ns_);
	step_.assign(ns_, kHalvings + 1);
	vertexOf_.resize(ns_);
	for (size_t v = 0; v < t_.nV; ++v)
		if (slot_[v] >= 0)
			vertexOf_[size_t(slot_[v])] = int32_t(v);
	for (size_t i = 0; i < ns_; ++i) {
		if (std::fabs(d_[i]) > pin_.limits.exact && normal_[i].Norm() > 0)
			step_[i] = 0;
		place(i);
	}
}

// Superface s's measures as accepted, back from its chunk's store.
void VertexPlacer::measuresBack(size_t c, int32_t s)
{
	const float *x = &store_[c][size_t(keptAt_[size_t(s)])];
	for (int32_t i = in_.faces.begin(s); i < in_.faces.end(s); ++i, x += 3) {
		const size_t f = size_t(in_.faces.face[size_t(i)]);
		m_.dev[f] = x[0], m_.gap[f] = x[1];
		if (tex_)
			m_.tex[f] = x[2];
	}
}

void VertexPlacer::markAround(size_t v, std::vector<uint8_t> &mark) const
{
	for (int32_t q = t_.vfStart[v]; q < t_.vfStart[v + 1]; ++q)
		mark[size_t(p_.label[size_t(t_.vfFace[size_t(q)])])] = 1;
}

// Superface s checked again with its vertices where they are now; its measures as accepted are
// kept (in chunk c's store) the first time; failed_[s] and its measures back if it fails.
void VertexPlacer::checkSuperface(size_t c, int32_t s, Scratch &w, ChunkOut &o)
{
	const Cached &cs = pin_.cache[size_t(s)];
	const size_t first = size_t(cs.triBegin), ntri = size_t(cs.triEnd - cs.triBegin);
	const int32_t fb = in_.faces.begin(s), fe = in_.faces.end(s);
	if (keptAt_[size_t(s)] < 0) {
		keptAt_[size_t(s)] = int32_t(store_[c].size());
		everChecked_[size_t(s)] = 1;
		for (int32_t i = fb; i < fe; ++i) {
			const size_t f = size_t(in_.faces.face[size_t(i)]);
			store_[c].push_back(m_.dev[f]);
			store_[c].push_back(m_.gap[f]);
			store_[c].push_back(tex_ ? m_.tex[f] : 0.0f);
		}
	}
	for (int32_t i = fb; i < fe; ++i) {
		const size_t f = size_t(in_.faces.face[size_t(i)]);
		m_.dev[f] = -1.0f, m_.gap[f] = 0.0f;
		if (tex_)
			m_.tex[f] = 0.0f;
	}
	// (the bound as accepted, plus the largest move of its vertices from there, bounds it too)
	const float before = accepted_[size_t(s)];
	double moves = 0;
	for (size_t k = first; k < first + ntri; ++k)
		for (size_t j = 0; j < 3; ++j)
			moves = std::max(moves, in_.moved(lt_.tris[3 * k + j]));
	w.boundCap = double(before) * (1 + 1e-6) + moves;
	w.boundEnough = kBoundEnough * double(levelBound_);
	Vec3 N;
	double bound = 0;
	o.truncate(0);
	bool ok = jobFromTriangles(in_, s, &lt_.tris[3 * first], &lt_.triBorder[first], ntri, N, w) &&
	          checkTriangles(in_, s, N, w, o, m_, bound) == Failure::None;
	w.boundCap = HUGE_VAL, w.boundEnough = 0;
	if (ok) { // (the level's bound does not grow)
		float after = 0;
		for (int32_t i = fb; i < fe; ++i)
			after = std::max(after, m_.gap[size_t(in_.faces.face[size_t(i)])]);
		ok = after <= std::max(before, levelBound_);
	}
	if (!ok) {
		failed_[size_t(s)] = 1;
		measuresBack(c, s);
	}
}

// The failed superfaces' vertices move half as far (then go back); the superfaces around them
// (the failed ones too) are to be checked again. False if no move changed.
bool VertexPlacer::halveFailed()
{
	std::fill(check_.begin(), check_.end(), uint8_t(0));
	bool again = false;
	std::fill(halved_.begin(), halved_.end(), uint8_t(0));
	for (size_t s = 0; s < nS_; ++s) {
		if (!failed_[s])
			continue;
		const Cached &cs = pin_.cache[s];
		for (size_t k = size_t(cs.triBegin); k < size_t(cs.triEnd); ++k)
			for (size_t j = 0; j < 3; ++j) {
				const size_t v = size_t(lt_.tris[3 * k + j]);
				const int32_t i = slot_[v];
				if (i < 0 || step_[size_t(i)] > kHalvings || halved_[size_t(i)])
					continue;
				halved_[size_t(i)] = 1; // (once per round, however many triangles hold it)
				++step_[size_t(i)];
				place(size_t(i));
				markAround(v, check_);
				again = true;
			}
	}
	return again;
}

// A superface checked with moved vertices that has none left is as accepted, measures too; the
// moves kept are counted.
void VertexPlacer::keepMoved()
{
	std::vector<uint8_t> anyMoved(nS_, 0);
	for (size_t i = 0; i < ns_; ++i)
		if (step_[i] <= kHalvings)
			markAround(size_t(vertexOf_[i]), anyMoved);
	for (size_t c = 0; c < chunks_.out.size(); ++c)
		for (int32_t s = chunks_.start[c]; s < chunks_.start[c + 1]; ++s)
			if (everChecked_[size_t(s)] && !anyMoved[size_t(s)])
				measuresBack(c, s);
	for (size_t i = 0; i < ns_; ++i)
		if (step_[i] <= kHalvings) {
			++out_.moved;
			out_.maxMove = std::max(out_.maxMove, std::fabs(moveOf(i)));
		}
}

void VertexPlacer::run()
{
	out_ = Placement();
	if (!(pin_.limits.maxDistance > 0) || nT_ == 0)
		return;
	if (!chooseSlots()) {
		out_ = Placement();
		return;
	}
	vertexNormals();
	traceInvolved();
	chunkSamples_.resize(chunks_.out.size());
	chunks_.forEach([&](size_t c, Scratch &w) { sampleChunk(c, w); });
	solveMoves();
	release(chunkSamples_);
	placeAll();
	// checks, until every superface with a moved vertex passes them; each superface's measures
	// as accepted are kept (per chunk) the first time it is checked, for when it fails or ends
	// with no vertex moved
	in_.placedSlot = slot_.data(), in_.placedP = out_.P.data();
	levelBound_ = *std::max_element(m_.gap.begin(), m_.gap.end());
	check_.assign(nS_, 0), failed_.assign(nS_, 0), keptAt_.assign(nS_, -1);
	store_.resize(chunks_.out.size());
	tex_ = !m_.tex.empty();
	for (size_t i = 0; i < ns_; ++i)
		if (step_[i] <= kHalvings)
			markAround(size_t(vertexOf_[i]), check_);
	everChecked_.assign(nS_, 0), halved_.resize(ns_);
	do {
		std::fill(failed_.begin(), failed_.end(), uint8_t(0));
		chunks_.forEach([&](size_t c, Scratch &w) {
			ChunkOut o;
			for (int32_t s = chunks_.start[c]; s < chunks_.start[c + 1]; ++s)
				if (check_[size_t(s)])
					checkSuperface(c, s, w, o);
		});
	} while (halveFailed()); // (each round that goes on halves or takes back a move: it ends)
	keepMoved();
	if (out_.moved == 0)
		out_ = Placement();
}

} // namespace

void placeVertices(const PlacementInput &pin, Chunks &chunks, Borders &b, Rings &rings,
                   FaceMeasures &m, Placement &out)
{
	VertexPlacer(pin, chunks, b, rings, m, out).run();
}

} // namespace detail
} // namespace gausslod
