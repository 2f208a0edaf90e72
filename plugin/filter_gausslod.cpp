// GaussLOD filter plugin: parameters in, gausslod::buildLevels(), one layer out per level.
// The algorithm itself lives in vcg_core/ (no Qt, no MeshLab there).

#include "filter_gausslod.h"
#include "level_layers.h"

#include <gausslod/gausslod.h>
#include <gausslod/vcg_adapter.h>

#include <QApplication>
#include <QStringList>
#include <QWidget>

#include <algorithm>
#include <cmath>
#include <memory>

namespace {

const char *const kFilterName = "Gauss Sphere LOD: Merge Near-Coplanar Faces";

/// What the dialog (or a script) asks for, after validation.
struct FilterRequest {
	gausslod::Params params;
	bool colourSuperfaces = true;
	bool overwriteColours = false;
	bool fauxEdges = true;
	bool selectedOnly = false;
};

/// The attributes of a layer that the levels carry (what its data mask says it has).
gausslod::MeshAttributes layerAttributes(const MeshModel &m)
{
	gausslod::MeshAttributes a;
	a.vertColor = m.hasDataMask(MeshModel::MM_VERTCOLOR);
	a.vertQuality = m.hasDataMask(MeshModel::MM_VERTQUALITY);
	a.vertTexCoord = m.hasDataMask(MeshModel::MM_VERTTEXCOORD);
	a.vertTexIndex = a.vertTexCoord && m.cm.textures.size() > 1;
	a.wedgeTexCoord = m.hasDataMask(MeshModel::MM_WEDGTEXCOORD);
	a.faceColor = m.hasDataMask(MeshModel::MM_FACECOLOR);
	return a;
}

/// MeshLab's main window when the filter runs in the GUI (none in meshlabserver).
QWidget *mainWindow()
{
	if (qobject_cast<QApplication *>(QCoreApplication::instance()) == nullptr)
		return nullptr;
	for (QWidget *w : QApplication::topLevelWidgets())
		if (w->inherits("MainWindow"))
			return w;
	return nullptr;
}

/// A RichAbsPerc value as a fraction of `diag`, the diagonal of the mesh the filter runs on. Its
/// percentage, (value-min)/(max-min), is what the dialog shows and what a saved script carries.
/// For parameters made by initParameterSet() on that mesh (min 0, max diag) this is value/diag;
/// a script written for another mesh (or with min 0 / max 100, as the project's default script)
/// keeps its percentage.
double fractionFromAbsPerc(const RichParameterList &par, const QString &name, double diag)
{
	const RichParameter &rp = par.getParameterByName(name);
	const double value = rp.value().getAbsPerc();
	const RichAbsPerc *ap = dynamic_cast<const RichAbsPerc *>(&rp);
	if (ap == nullptr || !(ap->max > ap->min))
		return diag > 0 ? value / diag : value; // (a value in mesh units)
	return (value - ap->min) / (double(ap->max) - ap->min);
}

/// The filter's list of targets for 'Levels by' (its engine form is "faces:" or "error:" and it).
const char *const kLevelTargets = "levelTargets";

/// The engine's "Levels by" text (parseLevelsBy) from the dialog or a script: the drop-down and
/// 'Targets', or (a script written when 'Levels by' was text) that text; none: angle.
std::string levelsByText(const RichParameterList &par)
{
	if (!par.hasParameter("levelsBy"))
		return "angle";
	const RichParameter &rp = par.getParameterByName("levelsBy");
	if (dynamic_cast<const RichEnum *>(&rp) == nullptr)
		return par.getString("levelsBy").toStdString();
	const std::string list =
	    par.hasParameter(kLevelTargets) ? par.getString(kLevelTargets).toStdString() : "";
	switch (par.getEnum("levelsBy")) {
		case 1: return "faces:" + list;
		case 2: return "error:" + list;
		default: return "angle";
	}
}

/// The engine's parameters from the dialog or a script, checked by the engine's validateParams.
bool readRequest(const RichParameterList &par, double diag, FilterRequest &req, QString &error)
{
	using gausslod::ParamKind;
	gausslod::Params &p = req.params;
	std::string outputLevels, levelsBy;
	for (const gausslod::ParamSpec &s : gausslod::paramSpecs()) {
		if (!s.inFilter)
			continue;
		switch (s.kind) {
			case ParamKind::Integer: gausslod::setParam(p, s, par.getInt(s.name)); break;
			case ParamKind::Real: gausslod::setParam(p, s, par.getFloat(s.name)); break;
			case ParamKind::Flag: gausslod::setParam(p, s, par.getBool(s.name)); break;
			case ParamKind::DiagonalFraction:
				gausslod::setParam(p, s, fractionFromAbsPerc(par, s.name, diag));
				break;
			case ParamKind::LevelList: outputLevels = par.getString(s.name).toStdString(); break;
			case ParamKind::LevelTargets: levelsBy = levelsByText(par); break;
		}
	}
	// levels by target: one level per target ('Number of levels' is then the number of targets)
	std::string message;
	gausslod::parseLevelsBy(levelsBy, p, message);
	if (message.empty())
		message = gausslod::validateParams(p);
	if (message.empty())
		gausslod::parseOutputLevels(outputLevels, p.maxLevel, p.outputLevels, message);
	if (!message.empty()) {
		error = QString::fromStdString(message) + ".";
		return false;
	}
	req.colourSuperfaces = par.getBool("colourSuperfaces");
	req.overwriteColours = par.getBool("overwriteColours");
	req.fauxEdges = par.getBool("fauxEdges");
	req.selectedOnly = par.getBool("selectedOnly");
	return true;
}

/// The dialog's parameter for `s`, with the engine's default (distances: that fraction of the
/// mesh's diagonal, in a 0..diag range).
std::unique_ptr<RichParameter> richParameter(const gausslod::ParamSpec &s, float diag)
{
	using gausslod::ParamKind;
	const QString name = s.name, label = s.label, tip = s.description;
	switch (s.kind) {
		case ParamKind::Integer:
			return std::unique_ptr<RichParameter>(
			    new RichInt(name, int(s.defaultValue), label, tip));
		case ParamKind::Real:
			return std::unique_ptr<RichParameter>(
			    new RichFloat(name, float(s.defaultValue), label, tip));
		case ParamKind::Flag:
			return std::unique_ptr<RichParameter>(
			    new RichBool(name, s.defaultValue != 0, label, tip));
		case ParamKind::DiagonalFraction:
			return std::unique_ptr<RichParameter>(
			    new RichAbsPerc(name, diag * float(s.defaultValue), 0.0f, diag, label, tip));
		case ParamKind::LevelTargets: // (a drop-down here; the list is kLevelTargets)
			return std::unique_ptr<RichParameter>(new RichEnum(
			    name, 0,
			    QStringList() << "The paper's angle levels"
			                  << "Face budgets"
			                  << "Error targets",
			    label,
			    "What sets the levels. The paper's angle levels: 'Number of levels' of them, level "
			    "i "
			    "merging faces whose normals lie in one of 3^i x 3^i Gauss-sphere cells per cube "
			    "face, each continued to a real step where its cells leave it too heavy ('Keep "
			    "every "
			    "level a real step'). Face budgets: one level per budget of 'Targets' (percentages "
			    "of "
			    "the input's faces, or counts), each with as many faces as fit; every budget is "
			    "reached, by edge collapses where merging cannot get there (only what the kept "
			    "materials and seams need can stop it: the log says so). Error targets: one level "
			    "per "
			    "distance of 'Targets' (% of the bounding-box diagonal), each with the fewest "
			    "faces "
			    "found whose proven distance to the input is within it."));
		case ParamKind::LevelList: break;
	}
	return std::unique_ptr<RichParameter>(new RichString(name, "all", label, tip));
}

} // namespace

FilterGaussLodPlugin::FilterGaussLodPlugin()
{
	typeList << FP_GAUSS_SPHERE_LOD;
	for (FilterIDType id : types())
		actionList << new QAction(filterName(id), this);
}

QString FilterGaussLodPlugin::pluginName() const { return "FilterGaussLod"; }

QString FilterGaussLodPlugin::filterName(FilterIDType filter) const
{
	switch (filter) {
		case FP_GAUSS_SPHERE_LOD: return kFilterName;
		default: assert(0); return QString();
	}
}

QString FilterGaussLodPlugin::filterInfo(FilterIDType filter) const
{
	switch (filter) {
		case FP_GAUSS_SPHERE_LOD:
			return "Builds levels of detail by merging near-coplanar faces: every face normal is "
			       "placed in a cell of a hierarchical Gauss sphere (a cube map split into "
			       "3<sup>i</sup> x 3<sup>i</sup> cells per face at level i), and connected faces "
			       "of "
			       "one cell form a <i>superface</i> whose normals differ by at most the cell's "
			       "bound "
			       "(sqrt(2)&middot;90&deg;/3<sup>i</sup>). "
			       "Borders are straightened, close border vertices merged, each superface "
			       "re-triangulated (constrained Delaunay); coarser levels merge superfaces of "
			       "sibling "
			       "cells, so the face count never grows. Beyond the paper: superfaces of "
			       "neighbouring "
			       "cells merge within the level's bound (on by default), and an optional distance "
			       "tolerance bounds how far a level moves the surface; 'Levels by' asks for "
			       "levels by "
			       "face budget or by distance tolerance instead of by angle. Each level becomes a "
			       "new layer "
			       "(the input is left untouched); the log gives per level the faces, superfaces, "
			       "fallbacks and measured deviation.<br><br>"
			       "See: <br><i>Cao Weiqun, Bao Hujun, Peng Qunsheng</i><br>"
			       "<b>\"An Algorithm for LOD by Merging Near Coplanar Faces Based on Gauss "
			       "Sphere\"</b><br>"
			       "Journal of Computer Science and Technology 16(5), 2001, pp. 450-457.";
		default: assert(0); return QString();
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

int FilterGaussLodPlugin::getPreConditions(QAction *) const { return MeshModel::MM_FACENUMBER; }

int FilterGaussLodPlugin::postCondition(QAction *) const
{
	return MeshModel::MM_NONE; // the input layer is not changed; results are new layers
}

void FilterGaussLodPlugin::initParameterSet(QAction *a, MeshModel &m, RichParameterList &par)
{
	switch (ID(a)) {
		case FP_GAUSS_SPHERE_LOD: {
			const float diag = m.cm.bbox.IsNull() ? 1.0f : m.cm.bbox.Diag();
			for (const gausslod::ParamSpec &s : gausslod::paramSpecs()) {
				if (s.inFilter)
					par.addParam(*richParameter(s, diag));
				if (s.kind == gausslod::ParamKind::LevelTargets)
					par.addParam(RichString(
					    kLevelTargets, "50%,25%,10%,5%,2%", "Targets",
					    "With 'Levels by' face budgets or error targets: a comma list, one level "
					    "per "
					    "target, in any order (the finest level gets the most faces or the "
					    "smallest "
					    "error; up to 8; 'Number of levels' is then their number). Face budgets: "
					    "percentages of the input's faces (50%,25%,10%) or face counts "
					    "(20000,5000). "
					    "Error targets: distances as percentages of the bounding-box diagonal "
					    "(0.01%,0.05%,0.2%). Not used by the paper's angle levels."));
			}
			par.addParam(
			    RichBool("selectedOnly", false, "Only selected faces",
			             "Simplify only the selected faces: unselected faces are kept exactly "
			             "as they are, and the border between them and the selection is "
			             "kept too (as in MeshLab's quadric edge collapse)."));
			par.addParam(RichBool(
			    "colourSuperfaces", true, "Colour faces by superface",
			    "Give every superface of an output level its own per-face colour, when the input "
			    "has "
			    "no colour of its own (no face or vertex colours, no texture coordinates): real "
			    "colours and textures are kept. See also 'Overwrite real colours'."));
			par.addParam(
			    RichBool("overwriteColours", false, "Overwrite real colours",
			             "With 'Colour faces by superface': colour the superfaces even when "
			             "the input has face or vertex colours or a texture (its face "
			             "colours are then replaced in the levels; the input is unchanged)."));
			par.addParam(RichBool("fauxEdges", true, "Mark superface interiors as faux edges",
			                      "Mark edges inside a superface as faux, so that MeshLab's "
			                      "polygonal wireframe draws "
			                      "each superface as one polygon."));
			break;
		}
		default: assert(0);
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
		default: assert(0); return false;
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

	FilterRequest req;
	QString error;
	gausslod::FlatMesh flat = gausslod::flatten(input->cm);
	if (!readRequest(par, gausslod::bboxDiagonal(flat.view()), req, error)) {
		errorMessage = error;
		return false;
	}
	if (req.selectedOnly && vcg::tri::UpdateSelection<CMeshO>::FaceCount(input->cm) == 0) {
		errorMessage = "'Only selected faces' is on, but no face of the layer is selected.";
		return false;
	}
	const gausslod::MeshAttributes attrs = layerAttributes(*input);
	QWidget *const gui = mainWindow();
	gausslod::addAttributes(input->cm, attrs, req.params, req.selectedOnly, flat);
	const gausslod::MeshView view = flat.view();
	const double diag = gausslod::bboxDiagonal(view);
	const Carried carried(attrs, req.colourSuperfaces, req.overwriteColours);

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
	if (!addLevelLayers(md, *input, result, flat, carried, req.fauxEdges, gui, diag, errorMessage))
		return false;
	for (const QString &line :
	     resultLog(*input, req.params, req.selectedOnly, result, carried, diag))
		Log(line.toStdString());
	return true;
}

MESHLAB_PLUGIN_NAME_EXPORTER(FilterGaussLodPlugin)
