// Wavefront OBJ import for Debian's MeshLab 2020.09, whose own (io_base's) aborts on any OBJ file.
//
// The same VCG importer io_base uses, with its index defect fixed and its input checked first
// (gausslod_io/obj_import.h), so files open as MeshLab's Windows build opens them: polygons
// triangulated, texture coordinates, materials (face colours, texture names), normals. Export
// stays io_base's, which works. MeshLab gives an extension to the first plugin in its plugins
// folder, by file name, that claims it; this plugin's file name sorts before libio_base.so.
#pragma once

#include <common/interfaces.h>

class GaussLodObjIOPlugin : public QObject, public MeshIOInterface {
	Q_OBJECT
	MESHLAB_PLUGIN_IID_EXPORTER(MESH_IO_INTERFACE_IID)
	Q_INTERFACES(MeshIOInterface)

public:
	QString pluginName() const override;
	QList<Format> importFormats() const override;
	QList<Format> exportFormats() const override;
	void GetExportMaskCapability(QString &format, int &capability, int &defaultBits) const override;
	bool open(const QString &format, const QString &fileName, MeshModel &m, int &mask,
	          const RichParameterList &par, vcg::CallBackPos *cb = nullptr,
	          QWidget *parent = nullptr) override;
	bool save(const QString &format, const QString &fileName, MeshModel &m, const int mask,
	          const RichParameterList &par, vcg::CallBackPos *cb = nullptr,
	          QWidget *parent = nullptr) override;
};
