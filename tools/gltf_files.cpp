// glb files by Debian's tinygltf, and the 3D Tiles tileset of a chain (gltf_files.h).
#include "gltf_files.h"

#include "cli.h"

#include <tiny_gltf.h>

#include <cstdio>
#include <fstream>
#include <iterator>
#include <sstream>

namespace cli {

std::string jsonString(const std::string &s)
{
	std::string out = "\"";
	for (const char c : s) {
		if (c == '"' || c == '\\') {
			out += '\\';
			out += c;
		} else if (static_cast<unsigned char>(c) < 0x20) {
			char buf[8];
			std::snprintf(buf, sizeof buf, "\\u%04x", unsigned(c));
			out += buf;
		} else {
			out += c;
		}
	}
	return out + "\"";
}

namespace {

// Appends `bytes` to the buffer as a new buffer view (4-byte aligned); returns its index.
int addView(tinygltf::Model &model, const void *bytes, size_t size, int target)
{
	std::vector<unsigned char> &data = model.buffers[0].data;
	while (data.size() % 4 != 0)
		data.push_back(0);
	tinygltf::BufferView view;
	view.buffer = 0;
	view.byteOffset = data.size();
	view.byteLength = size;
	view.target = target;
	const unsigned char *b = static_cast<const unsigned char *>(bytes);
	data.insert(data.end(), b, b + size);
	model.bufferViews.push_back(view);
	return int(model.bufferViews.size()) - 1;
}

int addAccessor(tinygltf::Model &model, const std::vector<float> &values, int type, int per)
{
	tinygltf::Accessor a;
	a.bufferView =
	    addView(model, values.data(), values.size() * sizeof(float), TINYGLTF_TARGET_ARRAY_BUFFER);
	a.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
	a.count = values.size() / size_t(per);
	a.type = type;
	model.accessors.push_back(a);
	return int(model.accessors.size()) - 1;
}

std::string lowerExtension(const std::string &file)
{
	const size_t dot = file.rfind('.');
	std::string e = dot == std::string::npos ? std::string() : file.substr(dot + 1);
	for (char &c : e)
		c = char(std::tolower(static_cast<unsigned char>(c)));
	return e;
}

// The image's texture index in the model, adding it (and its image) on first use; -1 if it
// cannot be embedded.
int textureOf(tinygltf::Model &model, std::map<std::string, int> &done, const std::string &file,
              std::string &warning)
{
	const auto it = done.find(file);
	if (it != done.end())
		return it->second;
	int id = -1;
	const std::string ext = lowerExtension(file);
	const char *mime = ext == "png"                    ? "image/png"
	                   : ext == "jpg" || ext == "jpeg" ? "image/jpeg"
	                                                   : nullptr;
	std::ifstream in(file, std::ios::binary);
	std::vector<unsigned char> bytes;
	if (mime && in)
		bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
	if (!mime || bytes.empty()) {
		warning += (warning.empty() ? "" : "; ") + std::string("texture ") + file +
		           (mime ? " could not be read" : " is not PNG or JPEG") + ": left out";
	} else {
		tinygltf::Image image;
		image.mimeType = mime;
		image.bufferView = addView(model, bytes.data(), bytes.size(), 0);
		model.images.push_back(image);
		tinygltf::Texture t;
		t.source = int(model.images.size()) - 1;
		model.textures.push_back(t);
		id = int(model.textures.size()) - 1;
	}
	done.emplace(file, id);
	return id;
}

// Adds `m` as a mesh and a node; returns the node's index.
int addMesh(tinygltf::Model &model, const GltfMesh &m, std::map<std::string, int> &textures,
            std::string &warning)
{
	tinygltf::Mesh mesh;
	const int pos = addAccessor(model, m.positions, TINYGLTF_TYPE_VEC3, 3);
	{
		tinygltf::Accessor &a = model.accessors[size_t(pos)];
		a.minValues.assign(3, HUGE_VAL);
		a.maxValues.assign(3, -HUGE_VAL);
		for (size_t i = 0; i + 2 < m.positions.size(); i += 3)
			for (int j = 0; j < 3; ++j) {
				a.minValues[size_t(j)] =
				    std::min(a.minValues[size_t(j)], double(m.positions[i + size_t(j)]));
				a.maxValues[size_t(j)] =
				    std::max(a.maxValues[size_t(j)], double(m.positions[i + size_t(j)]));
			}
		if (m.positions.empty())
			a.minValues.assign(3, 0.0), a.maxValues.assign(3, 0.0);
	}
	const int nrm = m.normals.empty() ? -1 : addAccessor(model, m.normals, TINYGLTF_TYPE_VEC3, 3);
	const int col = m.colours.empty() ? -1 : addAccessor(model, m.colours, TINYGLTF_TYPE_VEC4, 4);
	const int uv = m.uvs.empty() ? -1 : addAccessor(model, m.uvs, TINYGLTF_TYPE_VEC2, 2);
	for (size_t p = 0; p < m.primitives.size(); ++p) {
		if (m.primitives[p].empty())
			continue;
		const GltfMesh::Material &gm = m.materials[p];
		tinygltf::Material mat;
		mat.pbrMetallicRoughness.baseColorFactor = {gm.colour[0], gm.colour[1], gm.colour[2],
		                                            gm.colour[3]};
		mat.pbrMetallicRoughness.metallicFactor = 0;
		mat.pbrMetallicRoughness.roughnessFactor = 1;
		mat.doubleSided = true; // (a level's borders may show its back)
		if (gm.colour[3] < 1)
			mat.alphaMode = "BLEND";
		if (gm.texture >= 0 && uv >= 0 && size_t(gm.texture) < m.textures.size()) {
			const int t = textureOf(model, textures, m.textures[size_t(gm.texture)], warning);
			if (t >= 0)
				mat.pbrMetallicRoughness.baseColorTexture.index = t;
		}
		model.materials.push_back(mat);
		tinygltf::Accessor idx;
		idx.bufferView =
		    addView(model, m.primitives[p].data(), m.primitives[p].size() * sizeof(uint32_t),
		            TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
		idx.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
		idx.count = m.primitives[p].size();
		idx.type = TINYGLTF_TYPE_SCALAR;
		model.accessors.push_back(idx);
		tinygltf::Primitive prim;
		prim.mode = TINYGLTF_MODE_TRIANGLES;
		prim.indices = int(model.accessors.size()) - 1;
		prim.material = int(model.materials.size()) - 1;
		prim.attributes["POSITION"] = pos;
		if (nrm >= 0)
			prim.attributes["NORMAL"] = nrm;
		if (col >= 0)
			prim.attributes["COLOR_0"] = col;
		if (uv >= 0)
			prim.attributes["TEXCOORD_0"] = uv;
		mesh.primitives.push_back(prim);
	}
	model.meshes.push_back(mesh);
	tinygltf::Node node;
	node.mesh = int(model.meshes.size()) - 1;
	node.translation = {m.centre[0], m.centre[1], m.centre[2]};
	model.nodes.push_back(node);
	return int(model.nodes.size()) - 1;
}

} // namespace

bool writeGlb(const std::vector<const GltfMesh *> &meshes, const std::vector<double> &coverage,
              const std::string &path, std::string &warning, std::string &error, bool binary)
{
	tinygltf::Model model;
	model.asset.version = "2.0";
	model.asset.generator = "GaussLOD";
	model.buffers.resize(1);
	std::map<std::string, int> textures;
	std::vector<int> nodes;
	for (const GltfMesh *m : meshes)
		nodes.push_back(addMesh(model, *m, textures, warning));
	tinygltf::Scene scene;
	scene.nodes.push_back(nodes.empty() ? 0 : nodes[0]);
	if (nodes.size() > 1) {
		// MSFT_lod: the full-detail node lists the coarser ones; a viewer without the extension
		// shows the full detail
		tinygltf::Value::Array ids, cover;
		for (size_t i = 1; i < nodes.size(); ++i)
			ids.push_back(tinygltf::Value(nodes[i]));
		for (const double c : coverage)
			cover.push_back(tinygltf::Value(c));
		tinygltf::Value::Object lod;
		lod["ids"] = tinygltf::Value(ids);
		model.nodes[size_t(nodes[0])].extensions["MSFT_lod"] = tinygltf::Value(lod);
		tinygltf::Value::Object extras;
		extras["MSFT_screencoverage"] = tinygltf::Value(cover);
		model.nodes[size_t(nodes[0])].extras = tinygltf::Value(extras);
		model.extensionsUsed.push_back("MSFT_lod");
	}
	model.scenes.push_back(scene);
	model.defaultScene = 0;
	tinygltf::TinyGLTF gltf;
	if (!gltf.WriteGltfSceneToFile(&model, path, true, true, !binary, binary)) {
		error = "cannot write " + path;
		return false;
	}
	return true;
}

std::string tilesetJson(const std::vector<Tile> &tiles, const std::vector<double> &transform)
{
	double lo[3], hi[3];
	for (int j = 0; j < 3; ++j) {
		lo[j] = tiles[0].lo[j], hi[j] = tiles[0].hi[j];
		for (const Tile &t : tiles)
			lo[j] = std::min(lo[j], t.lo[j]), hi[j] = std::max(hi[j], t.hi[j]);
	}
	// (glTF content is y up; 3D Tiles turns it to z up: (x, y, z) -> (x, -z, y))
	const double c[3] = {0.5 * (lo[0] + hi[0]), -0.5 * (lo[2] + hi[2]), 0.5 * (lo[1] + hi[1])};
	const double h[3] = {0.5 * (hi[0] - lo[0]), 0.5 * (hi[2] - lo[2]), 0.5 * (hi[1] - lo[1])};
	const double diagonal = 2 * std::sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
	auto num = [](double x) {
		char b[64];
		std::snprintf(b, sizeof b, "%.17g", x);
		return std::string(b);
	};
	std::ostringstream box;
	box << "{\"box\":[" << num(c[0]) << "," << num(c[1]) << "," << num(c[2]) << "," << num(h[0])
	    << ",0,0,0," << num(h[1]) << ",0,0,0," << num(h[2]) << "]}";
	std::string json = "{\"asset\":{\"version\":\"1.1\",\"generator\":\"GaussLOD\"},"
	                   "\"geometricError\":" +
	                   num(diagonal) + ",\"root\":";
	std::string tail;
	for (size_t i = 0; i < tiles.size(); ++i) {
		const bool leaf = i + 1 == tiles.size();
		std::string t =
		    "{\"boundingVolume\":" + box.str() +
		    ",\"geometricError\":" + num(leaf ? 0.0 : tiles[i].error) +
		    ",\"refine\":\"REPLACE\",\"content\":{\"uri\":" + jsonString(tiles[i].content) +
		    "},\"extras\":{\"gausslod\":{\"lod\":" + std::to_string(tiles[i].lod) + ",\"level\":" +
		    (tiles[i].level < 0 ? std::string("null") : std::to_string(tiles[i].level)) +
		    ",\"faces\":" + std::to_string(tiles[i].faces) + "}}";
		if (i == 0 && transform.size() == 16) {
			t += ",\"transform\":[";
			for (size_t k = 0; k < 16; ++k)
				t += (k ? "," : "") + num(transform[k]);
			t += "]";
		}
		json += t + (leaf ? "}" : ",\"children\":[");
		if (!leaf)
			tail += "]}";
	}
	return json + tail + "}\n";
}

} // namespace cli
