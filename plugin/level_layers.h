// The GaussLOD filter's output (MeshLab glue): a layer per level, named by its figures, and the
// log's lines of a run (each level's from gausslod/level_figures.h).
#pragma once

#include <common/meshmodel.h>

#include <gausslod/gausslod.h>
#include <gausslod/vcg_adapter.h>

#include <QStringList>

class QWidget;

/// What the levels carry of the input layer: its attributes, but real colours replaced by
/// superface colours if asked (superface colours need per-face colour on the layer).
struct Carried {
	gausslod::MeshAttributes layer;  ///< the input layer's
	gausslod::MeshAttributes levels; ///< the levels'
	bool superfaceColours;           ///< faces coloured by superface
	Carried(const gausslod::MeshAttributes &a, bool colourSuperfaces, bool overwriteColours)
	    : layer(a), levels(a),
	      superfaceColours(colourSuperfaces && (!layerHasColour() || overwriteColours))
	{
		if (superfaceColours)
			levels.faceColor = false; // (its colours are replaced)
	}
	bool layerHasColour() const
	{
		return layer.vertColor || layer.faceColor || layer.wedgeTexCoord || layer.vertTexCoord;
	}
};

/// Adds a layer per level of `result` (made from `flat`, the input layer's, and carrying what `c`
/// says), the coarsest made current; `gui` is MeshLab's main window (null in meshlabserver). On
/// failure (memory) none is left and `error` says why.
bool addLevelLayers(MeshDocument &md, MeshModel &input, const gausslod::Result &result,
                    const gausslod::FlatMesh &flat, const Carried &c, bool fauxEdges, QWidget *gui,
                    double diag, QString &error);

/// The log's lines of a run: the input's repairs, what the levels carry, each level, the total.
QStringList resultLog(const MeshModel &input, const gausslod::Params &params, bool selectedOnly,
                      const gausslod::Result &result, const Carried &c, double diag);
