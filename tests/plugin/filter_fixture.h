// The GaussLOD plugin loaded from its .so (QPluginLoader, as MeshLab loads it), helpers to load
// real models into a MeshDocument, and the test fixture; shared by the plugin test files.
#pragma once

#include <common/filterscript.h>
#include <common/interfaces.h>
#include <common/meshmodel.h>

#include <wrap/gl/glu_tesselator.h> // import_off.h needs it for polygons
#include <wrap/io_trimesh/import_off.h>

#include <gtest/gtest.h>

#include <QCoreApplication>
#include <QFileInfo>
#include <QPluginLoader>
#include <QRegularExpression>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>
#include <vector>

namespace {

const QString kFilterName = "Gauss Sphere LOD: Merge Near-Coplanar Faces";

/// The plugin instance and its one action, loaded once for all tests.
struct LoadedFilter {
	QPluginLoader loader{QString(GAUSSLOD_PLUGIN_PATH)};
	MeshFilterInterface *filter = nullptr;
	QAction *action = nullptr;
	QString loadError;

	LoadedFilter()
	{
		QObject *instance = loader.instance();
		if (instance == nullptr) {
			loadError = loader.errorString();
			return;
		}
		filter = qobject_cast<MeshFilterInterface *>(instance);
		if (filter == nullptr) {
			loadError = "the plugin is not a MeshFilterInterface";
			return;
		}
		for (QAction *a : filter->actions())
			if (a->text() == kFilterName)
				action = a;
	}
};

LoadedFilter &plugin()
{
	static LoadedFilter loaded;
	return loaded;
}

QString dataFile(const char *name) { return QString(GAUSSLOD_DATA_DIR) + "/" + name; }

/// Adds a layer holding a real model read from an OFF file, labelled like MeshLab does ("cow.off").
MeshModel *loadOffLayer(MeshDocument &md, const QString &path)
{
	MeshModel *mm = md.addNewMesh(path, QFileInfo(path).fileName(), true);
	const int err = vcg::tri::io::ImporterOFF<CMeshO>::Open(mm->cm, qUtf8Printable(path));
	EXPECT_EQ(err, 0) << "cannot read " << qUtf8Printable(path) << ": "
	                  << vcg::tri::io::ImporterOFF<CMeshO>::ErrorMsg(err);
	mm->UpdateBoxAndNormals();
	return mm;
}

/// Every byte the filter could touch in a layer: sizes, positions, normals, flags, face indices.
/// Floats are kept as their bit patterns, so the comparison is byte-for-byte (NaN included).
struct LayerSnapshot {
	int vn = 0, fn = 0;
	size_t vertSlots = 0, faceSlots = 0;
	std::vector<uint32_t> vertexData; // P, N per vertex slot
	std::vector<int> vertexFlags, faceFlags;
	std::vector<int> faceVerts; // vertex slot index per face corner
	std::vector<uint32_t> faceNormals;
	int dataMask = 0;
	std::vector<uint32_t> box;

	static uint32_t bits(float x)
	{
		uint32_t b;
		std::memcpy(&b, &x, sizeof b);
		return b;
	}

	explicit LayerSnapshot(const MeshModel &mm)
	{
		const CMeshO &m = mm.cm;
		vn = m.vn, fn = m.fn;
		vertSlots = m.vert.size(), faceSlots = m.face.size();
		for (const auto &v : m.vert) {
			for (int k = 0; k < 3; ++k)
				vertexData.push_back(bits(v.cP()[k]));
			for (int k = 0; k < 3; ++k)
				vertexData.push_back(bits(v.cN()[k]));
			vertexFlags.push_back(v.cFlags());
		}
		for (const auto &f : m.face) {
			for (int k = 0; k < 3; ++k)
				faceVerts.push_back(int(f.cV(k) - &m.vert[0]));
			for (int k = 0; k < 3; ++k)
				faceNormals.push_back(bits(f.cN()[k]));
			faceFlags.push_back(f.cFlags());
		}
		dataMask = mm.dataMask();
		for (int k = 0; k < 3; ++k) {
			box.push_back(bits(m.bbox.min[k]));
			box.push_back(bits(m.bbox.max[k]));
		}
	}

	bool operator==(const LayerSnapshot &o) const
	{
		return vn == o.vn && fn == o.fn && vertSlots == o.vertSlots && faceSlots == o.faceSlots &&
		       vertexData == o.vertexData && vertexFlags == o.vertexFlags &&
		       faceVerts == o.faceVerts && faceNormals == o.faceNormals &&
		       faceFlags == o.faceFlags && dataMask == o.dataMask && box == o.box;
	}
};

struct ParsedLabel {
	QString base;
	int level = -1;
	long faces = -1;
	QString bound;
	double distancePct = -1; ///< the distance bound in the label (% of the diagonal), -1 = none
};

/// "cow LOD2 (5,706 f, <=14.1 deg)", with the distance tolerance "cow LOD2 (5,420 f, <=14.1 deg,
/// <=0.15 %)"; a level continued by collapses (DESIGN 51) has no angle: "cow LOD2 (1,858 f,
/// <=1.4 %)"
bool parseLabel(const QString &label, ParsedLabel &out)
{
	// (with the distance tolerance, the label ends with the level's distance bound)
	static const QRegularExpression re(
	    R"(^(.+) LOD(\d) \(([\d,]+) f(?:, <=([\d.]+) deg)?(?:, <=([\d.e-]+) %)?\)$)");
	const QRegularExpressionMatch m = re.match(label);
	if (!m.hasMatch())
		return false;
	out.base = m.captured(1);
	out.level = m.captured(2).toInt();
	out.faces = m.captured(3).remove(',').toLong();
	out.bound = m.captured(4);
	out.distancePct = m.captured(5).isEmpty() ? -1.0 : m.captured(5).toDouble();
	return true;
}

QString paperBound(int level)
{
	return QString::number(std::sqrt(2.0) * 90.0 / std::pow(3.0, level), 'g', 3);
}

bool hasFauxEdge(const CMeshO &m)
{
	for (const auto &f : m.face)
		if (!f.IsD() && (f.IsF(0) || f.IsF(1) || f.IsF(2)))
			return true;
	return false;
}

class GaussLodPlugin : public ::testing::Test {
protected:
	void SetUp() override
	{
		ASSERT_NE(plugin().filter, nullptr) << qUtf8Printable(plugin().loadError);
		ASSERT_NE(plugin().action, nullptr) << "no action named " << qUtf8Printable(kFilterName);
		filter = plugin().filter;
		action = plugin().action;
		log.Clear();
		filter->setLog(&log);
	}

	/// Default parameters for the current layer, as MeshLab's dialog would show them.
	RichParameterList defaults(MeshDocument &md)
	{
		RichParameterList par;
		filter->initParameterSet(action, md, par);
		return par;
	}

	bool apply(MeshDocument &md, const RichParameterList &par)
	{
		return filter->applyFilter(action, md, par, nullptr);
	}

	QStringList logLines()
	{
		QStringList lines;
		for (const auto &entry : log.logStringList())
			lines << entry.second;
		return lines;
	}

	/// A failing call: false, a message, and the document exactly as it was.
	void expectRejected(MeshDocument &md, const RichParameterList &par, const char *why)
	{
		const int layers = md.size();
		MeshModel *current = md.mm();
		const LayerSnapshot before(*current);
		EXPECT_FALSE(apply(md, par)) << why;
		EXPECT_FALSE(filter->errorMsg().isEmpty()) << why;
		EXPECT_EQ(md.size(), layers) << why << ": a layer was added";
		EXPECT_EQ(md.mm(), current) << why << ": the current layer changed";
		EXPECT_TRUE(LayerSnapshot(*current) == before) << why << ": the input changed";
	}

	MeshFilterInterface *filter = nullptr;
	QAction *action = nullptr;
	GLLogStream log;
};

} // namespace
