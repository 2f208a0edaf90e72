// GaussLOD filter plugin: parameters in, gausslod::buildLevels(), one layer out per level.
// The algorithm itself lives in vcg_core/ (no Qt, no MeshLab there).

#include "filter_gausslod.h"

#include <gausslod/gausslod.h>
#include <gausslod/vcg_adapter.h>

#include <QFileInfo>
#include <QLocale>

#include <algorithm>
#include <cmath>
#include <exception>

namespace {

const char *const kFilterName = "Gauss Sphere LOD: Merge Near-Coplanar Faces";
const int kMinLevels = 1;
const int kMaxLevels = 8;

/// What the dialog (or a script) asks for, after validation.
struct FilterRequest {
	gausslod::Params params;
	bool colourSuperfaces = true;
	bool fauxEdges = true;
};

QString thousands(size_t n)
{
	return QLocale(QLocale::English).toString(qulonglong(n));
}

/// A RichAbsPerc value in mesh units. Its percentage, (value-min)/(max-min), is what the dialog
/// shows and what a saved script carries: it is applied to `diag`, the diagonal of the mesh the
/// filter runs on. For parameters made by initParameterSet() on that mesh (min 0, max diag) this is
/// the value itself; a script written for another mesh (or with min 0 / max 100, as the project's
/// default script) keeps its percentage.
double absoluteFromAbsPerc(const RichParameterList &par, const QString &name, double diag)
{
	const RichParameter &rp = par.getParameterByName(name);
	const double value = rp.value().getAbsPerc();
	const RichAbsPerc *ap = dynamic_cast<const RichAbsPerc *>(&rp);
	if (ap == nullptr || !(ap->max > ap->min) || !(diag > 0))
		return value;
	return (value - ap->min) / (double(ap->max) - ap->min) * diag;
}

/// "all" or a comma-separated list of level indices (0 = coarsest .. maxLevel-1 = finest).
bool parseOutputLevels(const QString &text, int maxLevel, uint32_t &mask, QString &error)
{
	const QString t = text.trimmed();
	if (t.compare("all", Qt::CaseInsensitive) == 0) {
		mask = (maxLevel >= 32) ? 0xffffffffu : ((1u << maxLevel) - 1u);
		return true;
	}
	mask = 0;
	for (const QString &item : t.split(',')) {
		bool ok = false;
		const int level = item.trimmed().toInt(&ok);
		if (!ok || level < 0 || level >= maxLevel) {
			error =
			    QString("Output levels: '%1' is not a level index; write \"all\" or a comma "
			            "list of numbers from 0 (coarsest) to %2 (finest, = number of levels - 1).")
			        .arg(item.trimmed())
			        .arg(maxLevel - 1);
			return false;
		}
		mask |= 1u << level;
	}
	return true;
}

bool readRequest(const RichParameterList &par, double diag, FilterRequest &req, QString &error)
{
	gausslod::Params &p = req.params;
	p.maxLevel = par.getInt("maxLevel");
	if (p.maxLevel < kMinLevels || p.maxLevel > kMaxLevels) {
		error = QString("Number of levels must be in %1..%2 (got %3).")
		            .arg(kMinLevels)
		            .arg(kMaxLevels)
		            .arg(p.maxLevel);
		return false;
	}
	if (!parseOutputLevels(par.getString("outputLevels"), p.maxLevel, p.levelMask, error))
		return false;
	p.featureAngleDeg = par.getFloat("featureAngle");
	if (!(p.featureAngleDeg > 0 && p.featureAngleDeg < 180)) {
		error = QString("Feature angle must be between 0 and 180 degrees, exclusive (got %1).")
		            .arg(p.featureAngleDeg);
		return false;
	}
	p.straightenTolerance = absoluteFromAbsPerc(par, "straightenTol", diag);
	p.mergeDistance = absoluteFromAbsPerc(par, "mergeDist", diag);
	if (!std::isfinite(p.straightenTolerance) || p.straightenTolerance < 0) {
		error =
		    QString("Straightening tolerance must be >= 0 (got %1).").arg(p.straightenTolerance);
		return false;
	}
	if (!std::isfinite(p.mergeDistance) || p.mergeDistance < 0) {
		error = QString("Vertex merge distance must be >= 0 (got %1).").arg(p.mergeDistance);
		return false;
	}
	p.maxDistance = absoluteFromAbsPerc(par, "maxDistance", diag);
	if (!std::isfinite(p.maxDistance) || p.maxDistance < 0) {
		error = QString("Distance tolerance must be >= 0 (got %1).").arg(p.maxDistance);
		return false;
	}
	p.deviationFactor = par.getFloat("normalLimit");
	if (!std::isfinite(p.deviationFactor) || p.deviationFactor < 0) {
		error = QString("Normal deviation limit must be >= 0 (got %1).").arg(p.deviationFactor);
		return false;
	}
	p.mergeAcrossCells = par.getBool("acrossCells");
	p.weldVertices = par.getBool("weldVertices");
	p.weldDistance = absoluteFromAbsPerc(par, "weldDistance", diag);
	if (!std::isfinite(p.weldDistance) || p.weldDistance < 0) {
		error = QString("Weld distance must be >= 0 (got %1).").arg(p.weldDistance);
		return false;
	}
	req.colourSuperfaces = par.getBool("colourSuperfaces");
	req.fauxEdges = par.getBool("fauxEdges");
	return true;
}

/// Layer label without a file extension ("cow.off" -> "cow"); other labels are kept as they are.
QString baseLabel(const MeshModel &m)
{
	const QString label = m.label();
	const QString suffix = QFileInfo(label).suffix();
	const bool looksLikeExtension =
	    !suffix.isEmpty() && suffix.size() <= 4 &&
	    std::all_of(suffix.begin(), suffix.end(), [](QChar c) { return c.isLetterOrNumber(); }) &&
	    std::any_of(suffix.begin(), suffix.end(), [](QChar c) { return c.isLetter(); });
	return looksLikeExtension ? label.left(label.size() - suffix.size() - 1) : label;
}

/// "cow LOD2 (5,706 f, <=14.1 deg)"
QString levelLabel(const QString &base, const gausslod::LevelStats &s)
{
	return QString("%1 LOD%2 (%3 f, <=%4 deg)")
	    .arg(base)
	    .arg(s.level)
	    .arg(thousands(s.faces))
	    .arg(QString::number(s.boundDeg, 'g', 3));
}

QString levelLogLine(const gausslod::LevelStats &s, double diag)
{
	QString line =
	    QString("LOD%1 (%2x%2 cells per cube face, bound %3 deg): %4 faces, %5 vertices, "
	            "%6 superfaces, %7 fallbacks, %8 retriangulated; normal deviation "
	            "max %9 deg, mean %10 deg; %11 s")
	        .arg(s.level)
	        .arg(int(std::lround(std::pow(3.0, s.level))))
	        .arg(QString::number(s.boundDeg, 'g', 3))
	        .arg(thousands(s.faces))
	        .arg(thousands(s.vertices))
	        .arg(thousands(s.superfaces))
	        .arg(thousands(s.fallbacks))
	        .arg(thousands(s.retriangulated))
	        .arg(QString::number(s.maxNormalDevDeg, 'f', 2))
	        .arg(QString::number(s.meanNormalDevDeg, 'f', 2))
	        .arg(QString::number(s.seconds, 'f', 3));
	if (s.unmeasuredFaces > 0)
		line += QString(" (%1 input faces not measured)").arg(thousands(s.unmeasuredFaces));
	if (s.maxDistance >= 0 && diag > 0)
		line += QString("; distance bound %1 % of the diagonal (as the tolerance check measures it)")
		            .arg(QString::number(100.0 * s.maxDistance / diag, 'f', 4));
	if (s.reusedFiner)
		line += QString("; same mesh as LOD%1 (merging gave more faces)").arg(s.level + 1);
	return line;
}

} // namespace

FilterGaussLodPlugin::FilterGaussLodPlugin()
{
	typeList << FP_GAUSS_SPHERE_LOD;
	for (FilterIDType id : types())
		actionList << new QAction(filterName(id), this);
}

QString FilterGaussLodPlugin::pluginName() const
{
	return "FilterGaussLod";
}

QString FilterGaussLodPlugin::filterName(FilterIDType filter) const
{
	switch (filter) {
	case FP_GAUSS_SPHERE_LOD:
		return kFilterName;
	default:
		assert(0);
		return QString();
	}
}

QString FilterGaussLodPlugin::filterInfo(FilterIDType filter) const
{
	switch (filter) {
	case FP_GAUSS_SPHERE_LOD:
		return "Builds levels of detail by merging near-coplanar faces: every face normal is "
		       "placed in a cell of a hierarchical Gauss sphere (a cube map split into "
		       "3<sup>i</sup> x 3<sup>i</sup> cells per face at level i), and connected faces of "
		       "one cell form a <i>superface</i> whose normals differ by at most the cell's bound "
		       "(sqrt(2)&middot;90&deg;/3<sup>i</sup>). "
		       "Borders are straightened, close border vertices merged, each superface "
		       "re-triangulated (constrained Delaunay); coarser levels merge superfaces of sibling "
		       "cells, so the face count never grows. Beyond the paper: superfaces of neighbouring "
		       "cells merge within the level's bound (on by default), and an optional distance "
		       "tolerance bounds how far a level moves the surface. Each level becomes a new layer "
		       "(the input is left untouched); the log gives per level the faces, superfaces, "
		       "fallbacks and measured deviation.<br><br>"
		       "See: <br><i>Cao Weiqun, Bao Hujun, Peng Qunsheng</i><br>"
		       "<b>\"An Algorithm for LOD by Merging Near Coplanar Faces Based on Gauss "
		       "Sphere\"</b><br>"
		       "Journal of Computer Science and Technology 16(5), 2001, pp. 450-457.";
	default:
		assert(0);
		return QString();
	}
}

MeshFilterInterface::FilterClass FilterGaussLodPlugin::getClass(QAction *)
{
	return MeshFilterInterface::Remeshing;
}

MeshFilterInterface::FILTER_ARITY FilterGaussLodPlugin::filterArity(QAction *) const
{
	return SINGLE_MESH;
}

int FilterGaussLodPlugin::getPreConditions(QAction *) const
{
	return MeshModel::MM_FACENUMBER;
}

int FilterGaussLodPlugin::postCondition(QAction *) const
{
	return MeshModel::MM_NONE; // the input layer is not changed; results are new layers
}

void FilterGaussLodPlugin::initParameterSet(QAction *a, MeshModel &m, RichParameterList &par)
{
	switch (ID(a)) {
	case FP_GAUSS_SPHERE_LOD: {
		const float diag = m.cm.bbox.IsNull() ? 1.0f : m.cm.bbox.Diag();
		par.addParam(RichInt(
		    "maxLevel", 5, "Number of levels",
		    QString("How many levels of detail to build (the paper's MaxLevel), %1..%2. Level i "
		            "groups normals in 3^i x 3^i Gauss-sphere cells per cube face; its normal "
		            "deviation bound is sqrt(2)*90/3^i degrees: level 0 = 127 deg (coarsest), "
		            "1 = 42.4, 2 = 14.1, 3 = 4.71, 4 = 1.57 deg, ...")
		        .arg(kMinLevels)
		        .arg(kMaxLevels)));
		par.addParam(RichString(
		    "outputLevels", "all", "Output levels",
		    "Which levels become layers: \"all\", or a comma-separated list of level indices, "
		    "0 = coarsest to (number of levels - 1) = finest, e.g. \"0,2\". All levels are "
		    "computed either way, since each coarser level is made from the finer one."));
		par.addParam(RichFloat(
		    "featureAngle", 30.0f, "Feature angle (deg)",
		    "Angle in degrees (between 0 and 180) that classifies border vertices: a vertex "
		    "whose incident normals all lie within it is flat, one with two groups of normals "
		    "that each spread beyond it is a corner, else an edge vertex. Corners are never "
		    "merged away."));
		par.addParam(RichAbsPerc(
		    "straightenTol", diag * 0.005f, 0.0f, diag, "Border straightening tolerance",
		    "Distance in mesh units (the percentage is of the bounding-box diagonal; default "
		    "0.5%): a border vertex farther than this from the straightened border between two "
		    "superfaces is kept. 0 removes only exactly collinear border vertices. In a saved "
		    "script the percentage "
		    "is what is kept: it is applied to the diagonal of the mesh the script runs on."));
		par.addParam(RichAbsPerc(
		    "mergeDist", diag * 0.0025f, 0.0f, diag, "Vertex merge distance",
		    "Distance in mesh units (the percentage is of the bounding-box diagonal; default "
		    "0.25%): consecutive border vertices closer than this are merged, the less important "
		    "into the more important. 0 disables merging. In a saved script the percentage is "
		    "what is kept."));
		par.addParam(RichAbsPerc(
		    "maxDistance", 0.0f, 0.0f, diag, "Distance tolerance",
		    "Beyond the paper: distance in mesh units (the percentage is of the bounding-box "
		    "diagonal) that no removed input vertex may end farther than from the output. A "
		    "superface that would is retried with tighter borders, then split into finer "
		    "superfaces; it also caps the straightening tolerance (and the merge distance at "
		    "half of it). Coarse levels then keep more faces on curved parts. 0 = no distance "
		    "limit (default: only normals decide, as in the paper)."));
		par.addParam(RichFloat(
		    "normalLimit", 1.0f, "Normal deviation limit (x level bound)",
		    "Guarantee on the result, as a multiple of each level's bound sqrt(2)*90/3^i deg: "
		    "a superface whose re-triangulation leaves an input face farther than this from the "
		    "output triangle covering it is retried with tighter borders, then with its border "
		    "kept, then split into finer superfaces. 1 = the paper's bound (default); larger values simplify more; 0 = no "
		    "limit (only flipped triangles are refused)."));
		par.addParam(RichBool(
		    "acrossCells", true, "Merge across cell borders",
		    "Beyond the paper: also merge neighbouring superfaces of different Gauss-sphere "
		    "cells when all their face normals stay within the level's bound of each other (and "
		    "within the feature angle, so sharp edges stay sharp). Fewer faces on near-flat or "
		    "slightly noisy regions that a cell border would cut. Off = the paper's superfaces "
		    "(faces of one cell only)."));
		par.addParam(RichBool(
		    "weldVertices", true, "Weld coincident vertices",
		    "Vertices at exactly the same position are joined before simplifying (the first "
		    "one is kept), as MeshLab does to STL files on import: a triangle soup (STL, most "
		    "CAD and BIM exports) then has the shared edges its superfaces grow across. The "
		    "input layer is not changed; the log says how many were welded. Off = only vertices "
		    "that faces already share are joined."));
		par.addParam(RichAbsPerc(
		    "weldDistance", 0.0f, 0.0f, diag, "Weld distance",
		    "With welding on: vertices closer than this (mesh units; the percentage is of the "
		    "bounding-box diagonal) to an earlier kept vertex are joined to it too, for files "
		    "whose coincident vertices differ by rounding. 0 = exactly equal positions only "
		    "(default)."));
		par.addParam(RichBool("colourSuperfaces", true, "Colour faces by superface",
		                      "Give every superface of an output level its own per-face colour."));
		par.addParam(RichBool(
		    "fauxEdges", true, "Mark superface interiors as faux edges",
		    "Mark edges inside a superface as faux, so that MeshLab's polygonal wireframe draws "
		    "each superface as one polygon."));
		break;
	}
	default:
		assert(0);
	}
}

bool FilterGaussLodPlugin::applyFilter(QAction *a, MeshDocument &md, const RichParameterList &par,
                                       vcg::CallBackPos *cb)
{
	switch (ID(a)) {
	case FP_GAUSS_SPHERE_LOD: {
		errorMessage.clear();
		const bool ok = buildGaussSphereLods(md, par, cb);
		if (!ok) // meshlabserver prints the log but not errorMessage
			Log(GLLogStream::WARNING, ("GaussLOD failed: " + errorMessage).toStdString());
		return ok;
	}
	default:
		assert(0);
		return false;
	}
}

bool FilterGaussLodPlugin::buildGaussSphereLods(MeshDocument &md, const RichParameterList &par,
                                                vcg::CallBackPos *cb)
{
	MeshModel *input = md.mm();
	if (input == nullptr) {
		errorMessage = "No current layer.";
		return false;
	}
	if (input->cm.fn == 0) {
		errorMessage =
		    QString("Layer '%1' has no faces (%2 vertices): the Gauss sphere LOD needs a "
		            "triangle mesh.")
		        .arg(input->label())
		        .arg(input->cm.vn);
		return false;
	}

	const gausslod::FlatMesh flat = gausslod::flatten(input->cm);
	const gausslod::MeshView view = flat.view();
	FilterRequest req;
	QString error;
	const double diag = gausslod::bboxDiagonal(view);
	if (!readRequest(par, diag, req, error)) {
		errorMessage = error;
		return false;
	}

	const gausslod::Progress progress = [cb](double fraction, const char *stage) {
		if (cb == nullptr)
			return true;
		const int percent = int(std::lround(100.0 * std::min(1.0, std::max(0.0, fraction))));
		return cb(percent, stage);
	};
	const gausslod::Result result = gausslod::buildLevels(view, req.params, progress);
	if (!result.ok) {
		errorMessage = QString::fromStdString(result.error);
		return false;
	}
	if (result.levels.empty()) {
		errorMessage = "No level was produced (check the output levels).";
		return false;
	}

	// All checks passed: from here on only new layers are made; the input stays as it is.
	const QString base = baseLabel(*input);
	QList<MeshModel *> added;
	MeshModel *coarsest = nullptr;
	int coarsestLevel = 0;
	try {
		for (const gausslod::LevelMesh &level : result.levels) {
			MeshModel *lm = md.addNewMesh("", levelLabel(base, level.stats), true);
			added << lm;
			if (req.colourSuperfaces)
				lm->updateDataMask(MeshModel::MM_FACECOLOR);
			gausslod::toVcgMesh(level, lm->cm, req.colourSuperfaces, req.fauxEdges);
			lm->UpdateBoxAndNormals();
			if (coarsest == nullptr || level.stats.level < coarsestLevel) {
				coarsest = lm;
				coarsestLevel = level.stats.level;
			}
		}
	} catch (const std::exception &e) {
		for (MeshModel *lm : added)
			md.delMesh(lm);
		md.setCurrent(input);
		errorMessage = QString("Could not create the level layers: %1").arg(e.what());
		return false;
	}
	md.setCurrent(coarsest);

	const gausslod::InputStats &in = result.input;
	if (in.weldedVertices || in.facesSkipped() || in.facesDegenerate || in.verticesLocked)
		Log(QString("Input repairs (the input layer is unchanged): %1 vertices welded (%2 faces "
		            "re-indexed); %3 faces skipped (%4 with a repeated vertex, %5 repeating an "
		            "earlier face); %6 degenerate faces kept as they are; %7 vertices locked "
		            "(non-manifold or inconsistently oriented edges, non-manifold vertices)")
		        .arg(thousands(in.weldedVertices))
		        .arg(thousands(in.facesReindexed))
		        .arg(thousands(in.facesSkipped()))
		        .arg(thousands(in.facesRepeatedVertex))
		        .arg(thousands(in.facesDuplicate))
		        .arg(thousands(in.facesDegenerate))
		        .arg(thousands(in.verticesLocked))
		        .toStdString());
	for (const gausslod::LevelMesh &level : result.levels)
		Log(levelLogLine(level.stats, diag).toStdString());
	Log(QString(
	        "Gauss sphere LOD of '%1' (%2 faces, %3 vertices): %4 layer(s) added, %5 s in total")
	        .arg(input->label())
	        .arg(thousands(size_t(input->cm.fn)))
	        .arg(thousands(size_t(input->cm.vn)))
	        .arg(result.levels.size())
	        .arg(QString::number(result.totalSeconds, 'f', 3))
	        .toStdString());
	return true;
}

MESHLAB_PLUGIN_NAME_EXPORTER(FilterGaussLodPlugin)
