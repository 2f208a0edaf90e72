// The filter on layers that carry attributes (issue 14): real textured OBJ files with materials
// (Debian's assimp-testmodels, opened by our OBJ plugin as MeshLab opens them), vertex colours,
// the selection. Every level must carry what the input has, copied from it (never invented), and
// nothing it lacks; the input layer stays as it was.
#include "filter_fixture.h"

#include <QPluginLoader>

#include <array>
#include <set>
#include <tuple>

namespace {

/// Opens an OBJ file into a new layer with our OBJ plugin (as MeshLab's File > Import Mesh does).
MeshModel *loadObjLayer(MeshDocument &md, const QString &path)
{
	QPluginLoader loader(GAUSSLOD_OBJ_PLUGIN_PATH);
	auto *io = qobject_cast<MeshIOInterface *>(loader.instance());
	EXPECT_NE(io, nullptr) << qUtf8Printable(loader.errorString());
	MeshModel *mm = md.addNewMesh(path, QFileInfo(path).fileName(), true);
	if (io == nullptr)
		return mm;
	int mask = 0;
	RichParameterList none;
	EXPECT_TRUE(io->open("obj", path, *mm, mask, none, nullptr, nullptr))
	    << qUtf8Printable(io->errorMsg());
	mm->UpdateBoxAndNormals();
	return mm;
}

using Corner = std::tuple<std::array<float, 3>, float, float, short>; // position, u, v, texture
using Material = std::tuple<unsigned, short>;                         // face colour, texture

std::array<float, 3> position(const CVertexO *v) { return {{v->cP()[0], v->cP()[1], v->cP()[2]}}; }

unsigned rgba(const vcg::Color4b &c)
{
	return unsigned(c[0]) | unsigned(c[1]) << 8 | unsigned(c[2]) << 16 | unsigned(c[3]) << 24;
}

/// Every (position, wedge texture coordinates, texture index) of a layer's corners, and every
/// (face colour, texture index) of its faces.
void cornersAndMaterials(const CMeshO &m, std::set<Corner> &corners, std::set<Material> &materials)
{
	const bool wt = vcg::tri::HasPerWedgeTexCoord(m), fc = vcg::tri::HasPerFaceColor(m);
	for (const auto &f : m.face) {
		if (f.IsD())
			continue;
		for (int k = 0; k < 3; ++k)
			corners.emplace(position(f.cV(k)), wt ? f.cWT(k).u() : 0.f, wt ? f.cWT(k).v() : 0.f,
			                wt ? f.cWT(k).n() : short(-1));
		materials.emplace(fc ? rgba(f.cC()) : 0u, wt ? f.cWT(0).n() : short(-1));
	}
}

/// The level layers (1..n) of a document whose layer 0 is the input.
std::vector<MeshModel *> levels(MeshDocument &md)
{
	std::vector<MeshModel *> l;
	for (int i = 1; i < md.size(); ++i)
		l.push_back(md.meshList.at(i));
	return l;
}

/// Faces of layer `lm` whose wedge texture coordinates or material the input does not have. A
/// level continued by collapses (DESIGN 51: its label names no angle) places vertices where the
/// quadric is least, with the texture coordinates the input surface has there: new ones, finite.
void expectCarriedFrom(const std::set<Corner> &inCorners, const std::set<Material> &inMaterials,
                       const MeshModel &lm)
{
	std::set<Corner> corners;
	std::set<Material> materials;
	cornersAndMaterials(lm.cm, corners, materials);
	ParsedLabel label;
	ASSERT_TRUE(parseLabel(lm.label(), label)) << qUtf8Printable(lm.label());
	const bool placed = label.bound.isEmpty();
	size_t newCorners = 0, newMaterials = 0;
	for (const auto &f : lm.cm.face)
		for (int k = 0; k < 3 && vcg::tri::HasPerWedgeTexCoord(lm.cm); ++k)
			EXPECT_TRUE(std::isfinite(f.cWT(k).U()) && std::isfinite(f.cWT(k).V()));
	for (const Corner &c : corners)
		newCorners += !placed && inCorners.count(c) == 0;
	for (const Material &m : materials)
		newMaterials += inMaterials.count(m) == 0;
	EXPECT_EQ(newCorners, 0u) << qUtf8Printable(lm.label()) << ": corners with texture coordinates "
	                          << "the input has nowhere at that position";
	EXPECT_EQ(newMaterials, 0u) << qUtf8Printable(lm.label()) << ": materials the input lacks";
}

/// (A suite of its own: the fixture class of this file is not the other file's.)
class GaussLodAttributes : public GaussLodPlugin {};

} // namespace

TEST_F(GaussLodAttributes, textured_obj_with_materials_keeps_its_uvs_textures_and_materials)
{
	for (const char *name : {"spider.obj", "regr01.obj", "cube_usemtl.obj"}) {
		SCOPED_TRACE(name);
		log.Clear();
		MeshDocument md;
		MeshModel *input = loadObjLayer(md, QString(GAUSSLOD_OBJ_DIR) + "/" + name);
		ASSERT_GT(input->cm.fn, 0);
		const bool textured = input->hasDataMask(MeshModel::MM_WEDGTEXCOORD);
		ASSERT_TRUE(input->hasDataMask(MeshModel::MM_FACECOLOR)); // (the materials)
		const LayerSnapshot before(*input);
		std::set<Corner> inCorners;
		std::set<Material> inMaterials;
		cornersAndMaterials(input->cm, inCorners, inMaterials);

		ASSERT_TRUE(apply(md, defaults(md))) << qUtf8Printable(filter->errorMsg());
		EXPECT_TRUE(LayerSnapshot(*input) == before);
		ASSERT_EQ(md.size(), 6);
		for (MeshModel *lm : levels(md)) {
			EXPECT_EQ(lm->hasDataMask(MeshModel::MM_WEDGTEXCOORD), textured);
			EXPECT_TRUE(lm->hasDataMask(MeshModel::MM_FACECOLOR));
			EXPECT_FALSE(lm->hasDataMask(MeshModel::MM_VERTTEXCOORD)); // (the input has none)
			EXPECT_EQ(lm->cm.textures, input->cm.textures); // (headless: names as they are)
			expectCarriedFrom(inCorners, inMaterials, *lm);
		}
		const QStringList lines = logLines();
		const QStringList carried = lines.filter("Carried to the levels: ");
		ASSERT_EQ(carried.size(), 1) << qUtf8Printable(lines.join("\n"));
		EXPECT_TRUE(carried[0].contains("face colour"));
		EXPECT_EQ(carried[0].contains("vertex colour"),
		          input->hasDataMask(MeshModel::MM_VERTCOLOR));
		EXPECT_EQ(carried[0].contains("wedge texture coordinates"), textured);
		EXPECT_EQ(carried[0].contains("; textures: "), !input->cm.textures.empty());
		if (textured)
			EXPECT_EQ(lines.filter("texture coordinates moved at most").size(), 5);
	}
}

TEST_F(GaussLodAttributes, materials_stop_merging_unless_turned_off)
{
	MeshDocument md;
	MeshModel *input = loadObjLayer(md, QString(GAUSSLOD_OBJ_DIR) + "/regr01.obj");
	std::set<Corner> inCorners;
	std::set<Material> inMaterials;
	cornersAndMaterials(input->cm, inCorners, inMaterials);
	ASSERT_GT(inMaterials.size(), 1u);
	RichParameterList par = defaults(md);
	ASSERT_TRUE(apply(md, par)) << qUtf8Printable(filter->errorMsg());
	const int kept = md.meshList.at(5)->cm.fn;
	par.setValue("keepMaterials", BoolValue(false));
	par.setValue("keepSeams", BoolValue(false));
	par.setValue("maxTexError", FloatValue(0));
	md.setCurrent(input);
	ASSERT_TRUE(apply(md, par)) << qUtf8Printable(filter->errorMsg());
	ASSERT_EQ(md.size(), 11);
	const MeshModel *merged = md.meshList.at(10);
	EXPECT_LT(merged->cm.fn, kept) << "keeping materials apart changed nothing";
	// merged across materials, each output face still has the material of one input face
	std::set<Corner> corners;
	std::set<Material> materials;
	cornersAndMaterials(merged->cm, corners, materials);
	for (const Material &m : materials)
		EXPECT_EQ(inMaterials.count(m), 1u);
}

TEST_F(GaussLodAttributes, vertex_colours_are_the_input_vertices_and_superfaces_leave_them_alone)
{
	MeshDocument md;
	MeshModel *input = loadOffLayer(md, dataFile("fandisk.off"));
	input->updateDataMask(MeshModel::MM_VERTCOLOR);
	// two colours, split by a plane through the model
	const float mid = input->cm.bbox.Center()[0];
	for (auto &v : input->cm.vert)
		v.C() = v.cP()[0] < mid ? vcg::Color4b(200, 30, 30, 255) : vcg::Color4b(30, 30, 200, 255);
	const LayerSnapshot before(*input);
	// each level vertex is an input vertex, at its position or placed along its normal by at
	// most half the level's tolerance (0.16 % of the diagonal at LOD0): an input vertex that
	// near has its colour (copied, not blended: a blend of the two is neither)
	const double reach = (0.0016 + 1e-6) * double(input->cm.bbox.Diag()); // (+ float rounding)
	auto colourNear = [&](const CVertexO &w) {
		for (const auto &v : input->cm.vert)
			if (rgba(v.cC()) == rgba(w.cC()) &&
			    vcg::Distance(vcg::Point3d::Construct(v.cP()), vcg::Point3d::Construct(w.cP())) <=
			        reach)
				return true;
		return false;
	};

	ASSERT_TRUE(apply(md, defaults(md))) << qUtf8Printable(filter->errorMsg());
	EXPECT_TRUE(LayerSnapshot(*input) == before);
	for (MeshModel *lm : levels(md)) {
		SCOPED_TRACE(qUtf8Printable(lm->label()));
		EXPECT_TRUE(lm->hasDataMask(MeshModel::MM_VERTCOLOR));
		EXPECT_FALSE(lm->hasDataMask(MeshModel::MM_FACECOLOR))
		    << "superface colours over real ones";
		size_t wrong = 0;
		for (const auto &v : lm->cm.vert)
			wrong += !colourNear(v);
		EXPECT_EQ(wrong, 0u);
		EXPECT_LT(lm->cm.fn, input->cm.fn);
	}
	EXPECT_EQ(logLines().filter("superface colouring off (the layer has its own colours)").size(),
	          1);

	// asked to: superface colours on top (the vertex colours are still carried)
	RichParameterList par = defaults(md);
	par.setValue("overwriteColours", BoolValue(true));
	md.setCurrent(input);
	ASSERT_TRUE(apply(md, par)) << qUtf8Printable(filter->errorMsg());
	EXPECT_TRUE(md.meshList.at(10)->hasDataMask(MeshModel::MM_FACECOLOR));
	EXPECT_TRUE(md.meshList.at(10)->hasDataMask(MeshModel::MM_VERTCOLOR));
}

TEST_F(GaussLodAttributes, only_selected_faces_keeps_the_others_exactly)
{
	MeshDocument md;
	MeshModel *input = loadOffLayer(md, dataFile("fandisk.off"));
	RichParameterList par = defaults(md);
	par.setValue("selectedOnly", BoolValue(true));
	expectRejected(md, par, "nothing selected");
	EXPECT_TRUE(filter->errorMsg().contains("no face of the layer is selected"));

	const float mid = input->cm.bbox.Center()[0];
	using Tri = std::array<float, 9>;
	std::set<Tri> unselected;
	size_t selected = 0;
	for (auto &f : input->cm.face) {
		const float x = (f.cV(0)->cP()[0] + f.cV(1)->cP()[0] + f.cV(2)->cP()[0]) / 3;
		if (x > mid) {
			f.SetS();
			++selected;
			continue;
		}
		Tri t;
		for (int k = 0; k < 3; ++k)
			for (int j = 0; j < 3; ++j)
				t[size_t(3 * k + j)] = f.cV(k)->cP()[j];
		unselected.insert(t);
	}
	const LayerSnapshot before(*input);
	ASSERT_TRUE(apply(md, par)) << qUtf8Printable(filter->errorMsg());
	EXPECT_TRUE(LayerSnapshot(*input) == before);
	for (MeshModel *lm : levels(md)) {
		SCOPED_TRACE(qUtf8Printable(lm->label()));
		std::set<Tri> out;
		for (const auto &f : lm->cm.face)
			for (int s = 0; s < 3; ++s) { // (any rotation of the same corners)
				Tri t;
				for (int k = 0; k < 3; ++k)
					for (int j = 0; j < 3; ++j)
						t[size_t(3 * k + j)] = f.cV((k + s) % 3)->cP()[j];
				out.insert(t);
			}
		size_t missing = 0;
		for (const Tri &t : unselected)
			missing += out.count(t) == 0;
		EXPECT_EQ(missing, 0u);
		EXPECT_LT(size_t(lm->cm.fn), unselected.size() + selected); // the selection simplified
	}
	EXPECT_EQ(
	    logLines()
	        .filter(QString("Only selected faces: %1 unselected faces kept as they are")
	                    .arg(QLocale(QLocale::English).toString(qulonglong(unselected.size()))))
	        .size(),
	    1)
	    << qUtf8Printable(logLines().join("\n"));
}
