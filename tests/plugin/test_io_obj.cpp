// The GaussLOD OBJ plugin loaded headless (QPluginLoader, MeshLab's PluginManager) on real OBJ
// files that this project did not make (Debian's assimp-testmodels), checked against the files.
//
// Paths come from CMake: GAUSSLOD_OBJ_PLUGIN_PATH (the built .so), GAUSSLOD_IO_BASE_PATH (Debian's
// libio_base.so), GAUSSLOD_OBJ_DIR (assimp's models/OBJ), GAUSSLOD_INVALID_DIR (models/invalid).

#include <common/interfaces.h>
#include <common/meshmodel.h>
#include <common/pluginmanager.h>

#include <gtest/gtest.h>

#include <QCoreApplication>
#include <QDir>
#include <QFile>
#include <QFileInfo>
#include <QPluginLoader>
#include <QTemporaryDir>

#include <algorithm>
#include <cctype>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

namespace {

const QString kObjDir = GAUSSLOD_OBJ_DIR;

MeshIOInterface *objPlugin()
{
	// a fresh loader each time: a PluginManager deletes the instances it loaded
	QPluginLoader loader(GAUSSLOD_OBJ_PLUGIN_PATH);
	return qobject_cast<MeshIOInterface *>(loader.instance());
}

/// What an OBJ file and its MTL say, read here independently of VCG.
struct ObjFacts {
	int vertices = 0, normals = 0;
	std::vector<std::pair<float, float>> texCoords;
	long triangles = 0; // a face of k corners makes k-2
	struct Face {
		std::vector<int> texCoord; // 0-based, one per corner (-1 if none)
		std::string material;
	};
	std::vector<Face> faces;
	struct Material {
		float kd[3] = {1, 1, 1};
		float opacity = 1; // "d" (VCG reads "Tr" as the same)
		std::string texture;
	};
	std::map<std::string, Material> materials;

	static std::string rest(const std::string &line, size_t keyword)
	{
		return line.size() > keyword + 1 ? line.substr(keyword + 1) : std::string();
	}

	explicit ObjFacts(const std::string &path, const std::string &mtlOverride = "")
	{
		std::ifstream in(path);
		std::string line, material, mtl;
		while (std::getline(in, line)) {
			if (!line.empty() && line.back() == '\r')
				line.pop_back();
			std::istringstream words(line);
			std::string key;
			words >> key;
			if (key == "v")
				++vertices;
			else if (key == "vn")
				++normals;
			else if (key == "vt") {
				float u = 0, v = 0;
				words >> u >> v;
				texCoords.emplace_back(u, v);
			} else if (key == "usemtl")
				material = rest(line, 6);
			else if (key == "mtllib")
				mtl = rest(line, 6);
			else if (key == "f") {
				Face f;
				f.material = material;
				std::string corner;
				while (words >> corner) {
					const size_t slash = corner.find('/');
					const bool hasT = slash != std::string::npos && corner[slash + 1] != '/';
					f.texCoord.push_back(hasT ? std::stoi(corner.substr(slash + 1)) - 1 : -1);
				}
				if (f.texCoord.size() >= 3)
					triangles += long(f.texCoord.size()) - 2;
				faces.push_back(f);
			}
		}
		if (!mtlOverride.empty())
			mtl = mtlOverride;
		if (mtl.empty())
			return;
		std::ifstream m(path.substr(0, path.find_last_of('/') + 1) + mtl);
		Material *cur = nullptr;
		while (std::getline(m, line)) {
			if (!line.empty() && line.back() == '\r')
				line.pop_back();
			std::istringstream words(line);
			std::string key;
			words >> key;
			if (key == "newmtl")
				cur = &materials[rest(line, 6)];
			else if (cur != nullptr && key == "Kd")
				words >> cur->kd[0] >> cur->kd[1] >> cur->kd[2];
			else if (cur != nullptr && (key == "d" || key == "Tr"))
				words >> cur->opacity;
			else if (cur != nullptr && key == "map_Kd")
				cur->texture = rest(line, 6);
		}
	}

	bool trianglesOnly() const { return triangles == long(faces.size()); }
};

/// One layer of a MeshDocument, filled by the plugin's open().
struct Opened {
	MeshDocument md;
	MeshModel *mm = nullptr;
	bool ok = false;
	int mask = 0;
	QString error;

	explicit Opened(const QString &path)
	{
		mm = md.addNewMesh(path, QFileInfo(path).fileName(), true);
		MeshIOInterface *io = objPlugin();
		if (io == nullptr) {
			error = "plugin not loaded";
			return;
		}
		io->clearErrorString();
		RichParameterList none;
		ok = io->open("obj", path, *mm, mask, none, nullptr, nullptr);
		error = io->errorMsg();
	}
};

vcg::Color4b kdColour(const ObjFacts::Material &m)
{
	return vcg::Color4b((unsigned char)(m.kd[0] * 255.0), (unsigned char)(m.kd[1] * 255.0),
	                    (unsigned char)(m.kd[2] * 255.0), (unsigned char)(m.opacity * 255.0));
}

/// Every face of `o` against `facts`: texture coordinates and texture of each corner, colour.
void expectFacesMatch(const Opened &o, const ObjFacts &facts, const std::string &objDir)
{
	const CMeshO &m = o.mm->cm;
	ASSERT_TRUE(facts.trianglesOnly()) << "the face-by-face check needs a triangle file";
	ASSERT_EQ(size_t(m.fn), facts.faces.size());
	const bool textured = !facts.texCoords.empty();
	ASSERT_EQ(o.mm->hasDataMask(MeshModel::MM_WEDGTEXCOORD), textured);
	for (size_t i = 0; i < facts.faces.size(); ++i) {
		const ObjFacts::Face &f = facts.faces[i];
		const auto mat = facts.materials.find(f.material);
		for (int k = 0; textured && k < 3; ++k) {
			if (f.texCoord[k] < 0)
				continue; // a corner without "/vt" in a file with texture coordinates
			const auto &uv = facts.texCoords.at(size_t(f.texCoord[k]));
			ASSERT_FLOAT_EQ(m.face[i].cWT(k).u(), uv.first) << "face " << i << " corner " << k;
			ASSERT_FLOAT_EQ(m.face[i].cWT(k).v(), uv.second) << "face " << i << " corner " << k;
			if (mat != facts.materials.end() && !mat->second.texture.empty()) {
				const int n = m.face[i].cWT(k).n();
				ASSERT_GE(n, 0) << "face " << i;
				ASSERT_LT(size_t(n), m.textures.size());
				std::string want = mat->second.texture;
				std::replace(want.begin(), want.end(), '\\', '/');
				ASSERT_EQ(m.textures[size_t(n)], want) << "face " << i;
				ASSERT_TRUE(QFile::exists(QString::fromStdString(objDir + "/" + want))) << want;
			}
		}
		if (mat != facts.materials.end()) {
			ASSERT_TRUE(o.mm->hasDataMask(MeshModel::MM_FACECOLOR));
			ASSERT_EQ(m.face[i].cC(), kdColour(mat->second))
			    << "face " << i << " (material '" << f.material << "')";
		}
	}
}

std::string objPath(const char *name) { return (kObjDir + "/" + name).toStdString(); }

// ---- MeshLab gives .obj to this plugin ---------------------------------------------------------

/// The formats a PluginManager maps to plugins, loading the plugins of a folder holding `links`
/// (file name -> target).
struct Formats {
	QString objIn, objOut, plyIn;
};

Formats formatsWith(const std::map<QString, QString> &links)
{
	QTemporaryDir dir;
	for (const auto &l : links)
		EXPECT_TRUE(QFile::link(l.second, dir.filePath(l.first))) << qUtf8Printable(l.first);
	PluginManager pm;
	RichParameterList globals;
	pm.loadPlugins(globals, QDir(dir.path()));
	auto name = [](MeshIOInterface *p) { return p ? p->pluginName() : QString("none"); };
	return {name(pm.allKnowInputFormats.value("obj")), name(pm.allKnowOutputFormats.value("obj")),
	        name(pm.allKnowInputFormats.value("ply"))};
}

TEST(ObjPlugin, MeshLabOpensObjWithThisPluginAndKeepsIoBaseForTheRest)
{
	const Formats f = formatsWith({{"libio_base.so", GAUSSLOD_IO_BASE_PATH},
	                               {"libgausslod_io_obj.so", GAUSSLOD_OBJ_PLUGIN_PATH}});
	EXPECT_EQ(f.objIn, "GaussLodObjIO");
	EXPECT_EQ(f.objOut, "IOBase"); // io_base's OBJ export works
	EXPECT_EQ(f.plyIn, "IOBase");
}

TEST(ObjPlugin, TheFileNameOrderIsWhatGivesItObj)
{
	// the same plugin under a name sorting after libio_base.so loses .obj to io_base
	const Formats f = formatsWith(
	    {{"libio_base.so", GAUSSLOD_IO_BASE_PATH}, {"libio_zz_obj.so", GAUSSLOD_OBJ_PLUGIN_PATH}});
	EXPECT_EQ(f.objIn, "IOBase");
}

// ---- real files --------------------------------------------------------------------------------

TEST(ObjPlugin, OpensTheIssuesSingleTriangle)
{
	QTemporaryDir dir;
	const QString path = dir.filePath("triangle.obj");
	std::ofstream(path.toStdString()) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
	Opened o(path);
	ASSERT_TRUE(o.ok) << qUtf8Printable(o.error);
	EXPECT_EQ(o.mm->cm.vn, 3);
	EXPECT_EQ(o.mm->cm.fn, 1);
}

TEST(ObjPlugin, TexturedSpiderKeepsEveryFaceItsTexCoordsTexturesAndMaterials)
{
	const std::string path = objPath("spider.obj");
	const ObjFacts facts(path);
	ASSERT_EQ(facts.faces.size(), 1368u);
	ASSERT_GE(facts.materials.size(), 5u);
	Opened o(QString::fromStdString(path));
	ASSERT_TRUE(o.ok) << qUtf8Printable(o.error);
	EXPECT_TRUE(o.error.isEmpty()) << qUtf8Printable(o.error);
	EXPECT_EQ(o.mm->cm.vn, facts.vertices);
	EXPECT_EQ(o.mm->cm.textures.size(), 5u); // map_Kd names written with '\' in the MTL
	EXPECT_TRUE(o.mask & vcg::tri::io::Mask::IOM_WEDGTEXCOORD);
	expectFacesMatch(o, facts, kObjDir.toStdString());
}

TEST(ObjPlugin, MtllibWithSpacesInFolderAndFileName)
{
	QTemporaryDir tmp;
	const QString dir = tmp.filePath("a model folder");
	ASSERT_TRUE(QDir().mkpath(dir));
	for (const char *f : {"SpiderTex.jpg", "drkwood2.jpg", "engineflare1.jpg", "wal67ar_small.jpg",
	                      "wal69ar_small.jpg"})
		ASSERT_TRUE(QFile::copy(kObjDir + "/" + f, dir + "/" + f));
	ASSERT_TRUE(QFile::copy(kObjDir + "/spider.mtl", dir + "/spider materials.mtl"));
	{ // the real spider.obj, its mtllib line naming the renamed MTL
		std::ifstream in(objPath("spider.obj"));
		std::ofstream out((dir + "/spider model.obj").toStdString());
		std::string line;
		while (std::getline(in, line))
			out << (line.rfind("mtllib", 0) == 0 ? "mtllib spider materials.mtl\r" : line) << "\n";
	}
	const std::string path = (dir + "/spider model.obj").toStdString();
	const ObjFacts facts(path);
	ASSERT_EQ(facts.materials.size(), ObjFacts(objPath("spider.obj")).materials.size());
	Opened o(QString::fromStdString(path));
	ASSERT_TRUE(o.ok) << qUtf8Printable(o.error);
	EXPECT_TRUE(o.error.isEmpty()) << qUtf8Printable(o.error); // no "material file not found"
	EXPECT_EQ(o.mm->cm.textures.size(), 5u);
	expectFacesMatch(o, facts, dir.toStdString());
}

struct RealFile {
	const char *name;
	bool normals;  // has vn lines, faces refer to them
	bool polygons; // has faces of more than 3 corners
	bool facewise; // triangles only, every material found: checked face by face
};

class ObjPluginRealFiles : public ::testing::TestWithParam<RealFile> {};

TEST_P(ObjPluginRealFiles, EveryFaceIsRead)
{
	const RealFile &r = GetParam();
	const std::string path = objPath(r.name);
	const ObjFacts facts(path);
	Opened o(QString::fromStdString(path));
	ASSERT_TRUE(o.ok) << qUtf8Printable(o.error);
	EXPECT_EQ(o.mm->cm.vn, facts.vertices);
	EXPECT_EQ(o.mm->cm.fn, facts.triangles);
	EXPECT_EQ(!facts.trianglesOnly(), r.polygons);
	EXPECT_EQ(bool(o.mask & vcg::tri::io::Mask::IOM_BITPOLYGONAL), r.polygons);
	EXPECT_EQ(facts.normals > 0, r.normals); // "v//n" corners read (MeshLab recomputes normals)
	if (r.facewise)
		expectFacesMatch(o, facts, kObjDir.toStdString());
}

INSTANTIATE_TEST_SUITE_P(
    Assimp, ObjPluginRealFiles,
    ::testing::Values(RealFile{"WusonOBJ.obj", true, false, true}, // vt + vn, one vt for all
                      RealFile{"regr01.obj", false, false, true},  // 688 vt, 38 usemtl, mtllib ./
                      RealFile{"cube_usemtl.obj", true, false, true},     // usemtl per face, vn
                      RealFile{"concave_polygon.obj", true, true, false}, // one concave 66-gon
                      RealFile{"space_in_material_name.obj", true, true, false},
                      RealFile{"box_mat_with_spaces.obj", false, true, false},
                      RealFile{"cube_with_vertexcolors.obj", true, false, false}),
    [](const ::testing::TestParamInfo<RealFile> &info) {
	    std::string n = info.param.name;
	    n = n.substr(0, n.find('.'));
	    n.erase(std::remove(n.begin(), n.end(), '_'), n.end());
	    return n;
    });

// ---- bad input: a clear error, no crash, nothing half-read ------------------------------------

struct BadFile {
	const char *name;
	std::string content;  // written to a temporary file; empty: `name` is a real file
	const char *expected; // part of the error message
};

class ObjPluginBadInput : public ::testing::TestWithParam<BadFile> {};

TEST_P(ObjPluginBadInput, IsRefusedWithAClearError)
{
	const BadFile &b = GetParam();
	QTemporaryDir dir;
	QString path = QString(b.name).startsWith('/') ? QString(b.name) : dir.filePath(b.name);
	if (!b.content.empty())
		std::ofstream(path.toStdString(), std::ios::binary) << b.content;
	Opened o(path);
	EXPECT_FALSE(o.ok);
	EXPECT_TRUE(o.error.contains(b.expected)) << "message: " << qUtf8Printable(o.error);
	EXPECT_EQ(o.mm->cm.fn, 0);
}

const std::string kCube = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n";

INSTANTIATE_TEST_SUITE_P(
    Files, ObjPluginBadInput,
    ::testing::Values(
        BadFile{GAUSSLOD_INVALID_DIR "/empty.obj", "", "empty"},
        BadFile{GAUSSLOD_INVALID_DIR "/malformed.obj", "", "vertex 12 is not among the 8"},
        BadFile{GAUSSLOD_OBJ_DIR "/box_UTF16BE.obj", "", "No vertex found"},
        BadFile{"/nonexistent/model.obj", "", "does not exist"},
        BadFile{"forward.obj", kCube + "f 1 2 5\nv 2 2 0\n", "vertex 5 is not among the 4"},
        BadFile{"zero.obj", kCube + "f 0 1 2\n", "vertex 0 is not among"},
        BadFile{"relative.obj", kCube + "f -1 -2 -5\n", "vertex -5 is not among"},
        BadFile{"text.obj", kCube + "f 1 2 x\n", "'x' is not a vertex reference"},
        BadFile{"huge.obj", kCube + "f 1 2 99999999999\n", "is not a vertex reference"},
        BadFile{"texcoord.obj", kCube + "vt 0 0\nf 1/1 2/2 3/1\n", "texture coordinate of 2/2"},
        BadFile{"normal.obj", kCube + "vn 0 0 1\nf 1//1 2//1 3//2\n", "normal of 3//2"},
        BadFile{"line.obj", kCube + "l 1 9\n", "'9' is not one of the file's 4 vertices"},
        BadFile{"indented.obj", kCube + "  v 2 2 2\nf 1 2 3\n", "indented"},
        BadFile{"zbrush.obj", kCube + "#MRGB ff102030\nf 1 2 3\n", "colour 1 of its 4"},
        BadFile{"quads.obj", kCube + "q 0 1 2\n", "Quad faces"},
        BadFile{"shortvt.obj", kCube + "vt 0\nf 1 2 3\n", "Texture coords statement"}),
    [](const ::testing::TestParamInfo<BadFile> &info) {
	    std::string n = QFileInfo(info.param.name).baseName().toStdString();
	    n.erase(std::remove_if(n.begin(), n.end(), [](char c) { return !isalnum(c); }), n.end());
	    return n;
    });

} // namespace

int main(int argc, char **argv)
{
	QCoreApplication app(argc, argv);
	::testing::InitGoogleTest(&argc, argv);
	return RUN_ALL_TESTS();
}
