// The GaussLOD filter's output: a layer per level and the log's lines (level_layers.h).
#include "level_layers.h"

#include <gausslod/level_figures.h>
#include <gausslod/vcg_adapter.h>

#include <QApplication>
#include <QDir>
#include <QFileInfo>
#include <QLocale>
#include <QWidget>

#include <algorithm>
#include <cmath>
#include <exception>

namespace {

/// What the levels carry, as words the runner maps to meshlabserver's save options (vc, vq, vt,
/// wt, fc): "vertex colour, vertex quality, vertex texture coordinates, wedge texture
/// coordinates, face colour".
QString carriedText(const gausslod::MeshAttributes &a, bool superfaceColours)
{
	QStringList l;
	if (a.vertColor)
		l << "vertex colour";
	if (a.vertQuality)
		l << "vertex quality";
	if (a.vertTexCoord)
		l << "vertex texture coordinates";
	if (a.wedgeTexCoord)
		l << "wedge texture coordinates";
	if (a.faceColor)
		l << "face colour";
	else if (superfaceColours)
		l << "face colour (by superface)";
	return l.isEmpty() ? QString("geometry only") : l.join(", ");
}

/// In the GUI, a level's texture names are made absolute (next to the input's file) so that
/// MeshLab finds the images whatever its current folder; in meshlabserver they stay as the input
/// has them (relative to the input's folder, as the runner expects).
void levelTextures(const MeshModel &input, CMeshO &level, bool gui)
{
	level.textures = input.cm.textures;
	level.normalmaps = input.cm.normalmaps;
	if (!gui || input.fullName().isEmpty())
		return;
	const QDir dir = QFileInfo(input.fullName()).absoluteDir();
	for (std::string &t : level.textures) {
		const QString name = QString::fromStdString(t);
		if (QFileInfo(name).isRelative() && QFileInfo(dir.filePath(name)).exists())
			t = QDir::cleanPath(dir.absoluteFilePath(name)).toStdString();
	}
}

QString thousands(size_t n) { return QLocale(QLocale::English).toString(qulonglong(n)); }

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
QString levelLabel(const QString &base, const gausslod::LevelStats &s, double diag)
{
	// (a level continued by collapses, DESIGN 51, does not keep its cells' bound: not shown)
	QString label = QString("%1 LOD%2 (%3 f").arg(base).arg(s.level).arg(thousands(s.faces));
	if (!s.reduced)
		label += QString(", <=%1 deg").arg(QString::number(s.boundDeg, 'g', 3));
	// (the level's distance to the input, % of the diagonal: certified if it was, DESIGN 52,
	// else the construction's bound; both are proven)
	const double distance = s.hausdorff >= 0 ? s.hausdorff : s.distanceBound;
	if (distance >= 0 && diag > 0)
		label += QString(", <=%1 %").arg(QString::number(100.0 * distance / diag, 'g', 2));
	return label + ")";
}

/// The log's clause of a level made by edge collapses (DESIGN 50, 51) or the same as the finer
/// level (`collapses`: their number, as the log writes it).
QString collapseClause(const gausslod::LevelStats &s, const QString &collapses)
{
	QString clause;
	if (s.collapses > 0 && s.reduced)
		clause += QString("; continued from LOD%1 by %2 edge collapses with quadric placement "
		                  "(normal deviation measured against the input faces)")
		              .arg(s.level + 1)
		              .arg(collapses);
	else if (s.collapses > 0)
		clause += QString("; made from LOD%1 by %2 edge collapses (the superface level's face "
		                  "count within its distance bound; max normal deviation: a bound, mean: "
		                  "an estimate)")
		              .arg(s.level + 1)
		              .arg(collapses);
	if (s.reusedFiner)
		clause += QString("; same mesh as LOD%1 (merging gave more faces, or under 1 % fewer at a "
		                  "larger distance)")
		              .arg(s.level + 1);
	return clause;
}

/// The log's line of a level: its figures (gausslod/level_figures.h) in words.
QString levelLogLine(const gausslod::LevelStats &s, double diag, const gausslod::Params &p)
{
	const std::vector<gausslod::LevelFigure> figures = gausslod::levelFigures(s, diag, p);
	auto figure = [&](const char *key) -> const gausslod::LevelFigure & {
		return gausslod::figure(figures, key);
	};
	auto count = [&](const char *key) { return thousands(size_t(figure(key).value)); };
	auto fixed = [&](const char *key, int decimals) {
		return QString::number(figure(key).value, 'f', decimals);
	};
	auto digits = [&](const char *key, int n) {
		return QString::number(figure(key).value, 'g', n);
	};
	QString line =
	    QString("LOD%1 (%2x%2 cells per cube face, bound %3 deg): %4 faces, %5 vertices, "
	            "%6 superfaces, %7 fallbacks, %8 retriangulated; normal deviation "
	            "max %9 deg, mean %10 deg; %11 s")
	        .arg(s.level)
	        .arg(int(std::lround(std::pow(3.0, s.level))))
	        .arg(digits("bound_deg", 3))
	        .arg(count("faces"))
	        .arg(count("vertices"))
	        .arg(count("superfaces"))
	        .arg(count("fallbacks"))
	        .arg(count("retriangulated"))
	        .arg(fixed("max_dev_deg", 2))
	        .arg(fixed("mean_dev_deg", 2))
	        .arg(fixed("seconds", 3));
	if (figure("unmeasured_faces").value > 0)
		line += QString(" (%1 input faces not measured)").arg(count("unmeasured_faces"));
	if (figure("max_tex_error").known)
		line += QString("; texture coordinates moved at most %1 (UV units)")
		            .arg(digits("max_tex_error", 3));
	if (figure("distance_bound_pct").known)
		line += QString("; distance to the input at most %1 % of the diagonal (%2, a proven bound)")
		            .arg(fixed("distance_bound_pct", 4))
		            .arg(digits("distance_bound", 4));
	if (figure("hausdorff_pct").known)
		line += QString("; Hausdorff distance to the input certified at most %1 % of the diagonal "
		                "(%2; at least %3 %, measured at a point%4; %5 s)")
		            .arg(fixed("hausdorff_pct", 4))
		            .arg(digits("hausdorff", 4))
		            .arg(fixed("hausdorff_lower_pct", 4))
		            .arg(figure("hausdorff_converged").value != 0
		                     ? ""
		                     : "; the search stopped at its work limit")
		            .arg(fixed("seconds_hausdorff", 3));
	if (figure("placed_vertices").value > 0 && diag > 0)
		line += QString("; %1 vertices placed on the surface (moved at most %2 % of the diagonal)")
		            .arg(count("placed_vertices"))
		            .arg(fixed("max_placement_pct", 4));
	line += collapseClause(s, count("collapses"));
	if (figure("target_faces").value > 0 || figure("target_error_pct").known)
		line += QString("; target %1 %2, distance tolerance %3 % of the diagonal (%4 build%5)")
		            .arg(figure("target_error_pct").known
		                     ? QString("%1 % of the diagonal").arg(digits("target_error_pct", 6))
		                     : QString("%1 faces").arg(count("target_faces")))
		            .arg(figure("target_reached").value != 0 ? "reached"
		                 : figure("target_error_pct").known
		                     ? "NOT reached (measured above it)"
		                     : "NOT reached (" + count("faces") + " faces: " +
		                           QString::fromStdString(gausslod::budgetNote(s)) + ")")
		            .arg(digits("tolerance_pct", 4))
		            .arg(int(figure("trials").value))
		            .arg(figure("trials").value == 1 ? "" : "s");
	return line;
}

} // namespace

bool addLevelLayers(MeshDocument &md, MeshModel &input, const gausslod::Result &result,
                    const gausslod::FlatMesh &flat, const Carried &c, bool fauxEdges, QWidget *gui,
                    double diag, QString &error)
{
	const QString base = baseLabel(input);
	QList<MeshModel *> added;
	MeshModel *coarsest = nullptr;
	int coarsestLevel = 0;
	try {
		for (const gausslod::LevelMesh &level : result.levels) {
			MeshModel *lm = md.addNewMesh("", levelLabel(base, level.stats, diag), true);
			added << lm;
			int mask = c.superfaceColours || c.levels.faceColor ? MeshModel::MM_FACECOLOR : 0;
			mask |= c.levels.vertColor ? MeshModel::MM_VERTCOLOR : 0;
			mask |= c.levels.vertQuality ? MeshModel::MM_VERTQUALITY : 0;
			mask |= c.levels.vertTexCoord ? MeshModel::MM_VERTTEXCOORD : 0;
			mask |= c.levels.wedgeTexCoord ? MeshModel::MM_WEDGTEXCOORD : 0;
			if (mask)
				lm->updateDataMask(mask);
			gausslod::toVcgMeshWithAttributes(level, flat, input.cm, c.levels, lm->cm,
			                                  c.superfaceColours, fauxEdges);
			levelTextures(input, lm->cm, gui != nullptr);
			lm->UpdateBoxAndNormals(); // (per-vertex normals of the new faces, smooth)
			if (coarsest == nullptr || level.stats.level < coarsestLevel) {
				coarsest = lm;
				coarsestLevel = level.stats.level;
			}
		}
	} catch (const std::exception &e) {
		for (MeshModel *lm : added)
			md.delMesh(lm);
		md.setCurrent(&input);
		error = QString("Could not create the level layers: %1").arg(e.what());
		return false;
	}
	md.setCurrent(coarsest);
	if (gui != nullptr && !input.cm.textures.empty())
		for (MeshModel *lm : added) // (MeshLab loads the images of the current layer only)
			QMetaObject::invokeMethod(gui, "updateTexture", Qt::QueuedConnection,
			                          Q_ARG(int, lm->id()));
	return true;
}

QStringList resultLog(const MeshModel &input, const gausslod::Params &params, bool selectedOnly,
                      const gausslod::Result &result, const Carried &c, double diag)
{
	QStringList lines;
	const gausslod::InputStats &in = result.input;
	if (in.weldedVertices || in.facesSkipped() || in.facesDegenerate || in.verticesLocked)
		lines << QString(
		             "Input repairs (the input layer is unchanged): %1 vertices welded (%2 faces "
		             "re-indexed); %3 faces skipped (%4 with a repeated vertex, %5 repeating an "
		             "earlier face); %6 degenerate faces kept as they are; %7 vertices locked "
		             "(non-manifold or inconsistently oriented edges, non-manifold vertices%8)")
		             .arg(thousands(in.weldedVertices))
		             .arg(thousands(in.facesReindexed))
		             .arg(thousands(in.facesSkipped()))
		             .arg(thousands(in.facesRepeatedVertex))
		             .arg(thousands(in.facesDuplicate))
		             .arg(thousands(in.facesDegenerate))
		             .arg(thousands(in.verticesLocked))
		             .arg(selectedOnly ? ", unselected faces" : "");
	if (in.coplanarRegions)
		lines
		    << QString(
		           "Coplanar regions: %1 regions of faces in one plane re-triangulated before the "
		           "levels (%2 faces -> %3; the same surface, within %4)")
		           .arg(thousands(in.coplanarRegions))
		           .arg(thousands(input.cm.fn))
		           .arg(thousands(in.facesAfterCoplanar))
		           .arg(in.coplanarDistance, 0, 'g', 3);
	if (selectedOnly)
		lines << QString("Only selected faces: %1 unselected faces kept as they are in every level")
		             .arg(thousands(in.facesKept));
	QStringList textures;
	for (const std::string &t : input.cm.textures)
		textures << QString::fromStdString(t);
	lines << QString("Carried to the levels: %1%2%3")
	             .arg(carriedText(c.levels, c.superfaceColours))
	             .arg(textures.isEmpty() ? QString()
	                                     : QString("; textures: %1").arg(textures.join(" | ")))
	             .arg(c.layerHasColour()
	                      ? c.superfaceColours
	                            ? "; real colours replaced by superface colours (asked)"
	                            : "; superface colouring off (the layer has its own colours)"
	                      : "");
	if (!params.levelFaces.empty() || !params.levelDistances.empty())
		lines << QString("Levels by %1: %2 levels, one per target")
		             .arg(QString::fromStdString(gausslod::levelsByText(params)))
		             .arg(params.maxLevel);
	for (const gausslod::LevelMesh &level : result.levels)
		lines << levelLogLine(level.stats, diag, params);
	lines
	    << QString(
	           "Gauss sphere LOD of '%1' (%2 faces, %3 vertices): %4 layer(s) added, %5 s in total")
	           .arg(input.label())
	           .arg(thousands(size_t(input.cm.fn)))
	           .arg(thousands(size_t(input.cm.vn)))
	           .arg(result.levels.size())
	           .arg(QString::number(result.totalSeconds, 'f', 3));
	return lines;
}
