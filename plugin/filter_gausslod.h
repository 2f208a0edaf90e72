// GaussLOD filter plugin for MeshLab 2020.09: MeshLab glue around the engine in vcg_core/.
//
// One filter, "Gauss Sphere LOD: Merge Near-Coplanar Faces". It reads the current layer, builds the
// requested levels of detail with gausslod::buildLevels() and adds one new layer per level; the
// input layer is never modified. On any error nothing is added and errorMessage says why.
#pragma once

#include <common/interfaces.h>

class FilterGaussLodPlugin : public QObject, public MeshFilterInterface {
	Q_OBJECT
	MESHLAB_PLUGIN_IID_EXPORTER(MESH_FILTER_INTERFACE_IID)
	Q_INTERFACES(MeshFilterInterface)

public:
	enum { FP_GAUSS_SPHERE_LOD };

	FilterGaussLodPlugin();

	QString pluginName() const override;
	QString filterName(FilterIDType filter) const override;
	QString filterInfo(FilterIDType filter) const override;
	FilterClass getClass(QAction *a) override;
	FILTER_ARITY filterArity(QAction *a) const override;
	int getPreConditions(QAction *a) const override;
	int postCondition(QAction *a) const override;
	using MeshFilterInterface::initParameterSet;
	void initParameterSet(QAction *a, MeshModel &m, RichParameterList &par) override;
	bool applyFilter(QAction *a, MeshDocument &md, const RichParameterList &par,
	                 vcg::CallBackPos *cb) override;

private:
	bool buildGaussSphereLods(MeshDocument &md, const RichParameterList &par, vcg::CallBackPos *cb);
};
