// mesh_facts FILE: reads FILE with the guarded VCG importers (gausslod_io, the mesh type with
// every attribute the tool carries) and prints one JSON object of what it holds: counts, the
// attributes read, texture names, materials, and the distinct values of each attribute, so that
// a test can compare a level with its input without trusting the tool's own report.
#include "gausslod_io/import_mesh.h"

#include <cmath>
#include <cstdio>
#include <set>
#include <string>
#include <tuple>

namespace {

std::string str(const std::string &s)
{
	std::string out = "\"";
	for (const char c : s) {
		if (c == '"' || c == '\\')
			out += '\\', out += c;
		else if (static_cast<unsigned char>(c) < 0x20)
			out += '?';
		else
			out += c;
	}
	return out + "\"";
}

template <class Set, class Fn>
std::string list(const Set &s, Fn item)
{
	std::string out = "[";
	for (const auto &x : s)
		out += (out.size() > 1 ? "," : "") + item(x);
	return out + "]";
}

std::string colour(const std::tuple<int, int, int, int> &c)
{
	char b[64];
	std::snprintf(b, sizeof b, "[%d,%d,%d,%d]", std::get<0>(c), std::get<1>(c), std::get<2>(c),
	              std::get<3>(c));
	return b;
}

std::string uv(const std::tuple<float, float, int> &t)
{
	char b[96];
	std::snprintf(b, sizeof b, "[%.9g,%.9g,%d]", double(std::get<0>(t)), double(std::get<1>(t)),
	              std::get<2>(t));
	return b;
}

} // namespace

int main(int argc, char **argv)
{
	if (argc != 2) {
		std::fprintf(stderr, "usage: mesh_facts FILE\n");
		return 2;
	}
	using Mask = vcg::tri::io::Mask;
	gausslod::IoAttrMesh m;
	gausslod::ReadError e;
	gausslod::ReadInfo info;
	if (!gausslod::importMesh(m, argv[1], e, &info)) {
		std::printf("{\"ok\":false,\"error\":%s}\n", str(e.message).c_str());
		return 1;
	}
	const int mask = info.mask;
	std::set<std::tuple<int, int, int, int>> faceColours, vertexColours;
	std::set<std::tuple<float, float, int>> wedgeUV, vertexUV;
	std::set<int> texIndex;
	std::set<std::pair<std::tuple<int, int, int, int>, std::string>> faceMaterials;
	std::set<float> quality;
	double normalError = 0;
	std::set<std::tuple<float, float, float>> normals;
	for (const auto &v : m.vert) {
		if (v.IsD())
			continue;
		if (mask & Mask::IOM_VERTCOLOR)
			vertexColours.emplace(v.cC()[0], v.cC()[1], v.cC()[2], v.cC()[3]);
		if (mask & Mask::IOM_VERTTEXCOORD)
			vertexUV.emplace(v.cT().u(), v.cT().v(), 0);
		if (mask & Mask::IOM_VERTQUALITY)
			quality.insert(v.cQ());
		if (mask & Mask::IOM_VERTNORMAL) {
			normalError = std::max(normalError, std::fabs(double(v.cN().Norm()) - 1.0));
			normals.emplace(v.cN()[0], v.cN()[1], v.cN()[2]);
		}
	}
	for (const auto &f : m.face) {
		if (f.IsD())
			continue;
		if (mask & Mask::IOM_FACECOLOR)
			faceColours.emplace(f.cC()[0], f.cC()[1], f.cC()[2], f.cC()[3]);
		if (mask & Mask::IOM_WEDGTEXCOORD)
			for (int k = 0; k < 3; ++k) {
				wedgeUV.emplace(f.cWT(k).u(), f.cWT(k).v(), f.cWT(k).n());
				texIndex.insert(f.cWT(k).n());
			}
		// a face's material: its colour and the texture its corners name
		if (mask & (Mask::IOM_FACECOLOR | Mask::IOM_WEDGTEXCOORD)) {
			const int n = (mask & Mask::IOM_WEDGTEXCOORD) ? f.cWT(0).n() : -1;
			const auto c = (mask & Mask::IOM_FACECOLOR)
			                   ? std::make_tuple(int(f.cC()[0]), int(f.cC()[1]), int(f.cC()[2]),
			                                     int(f.cC()[3]))
			                   : std::make_tuple(-1, -1, -1, -1);
			faceMaterials.emplace(c, n >= 0 && size_t(n) < m.textures.size() ? m.textures[size_t(n)]
			                                                                 : std::string());
		}
	}
	const std::pair<int, const char *> names[] = {
	    {Mask::IOM_VERTNORMAL, "vertex_normal"},   {Mask::IOM_VERTCOLOR, "vertex_colour"},
	    {Mask::IOM_VERTQUALITY, "vertex_quality"}, {Mask::IOM_VERTTEXCOORD, "vertex_uv"},
	    {Mask::IOM_WEDGTEXCOORD, "wedge_uv"},      {Mask::IOM_FACECOLOR, "face_colour"}};
	std::string attributes = "[";
	for (const auto &n : names)
		if (mask & n.first)
			attributes += std::string(attributes.size() > 1 ? "," : "") + "\"" + n.second + "\"";
	attributes += "]";
	std::set<std::string> mapKd;
	for (const auto &mat : info.materials)
		if (!mat.map_Kd.empty())
			mapKd.insert(mat.map_Kd);
	auto qual = [](float q) {
		char b[32];
		std::snprintf(b, sizeof b, "%.9g", double(q));
		return std::string(b);
	};
	std::printf(
	    "{\"ok\":true,\"vertices\":%d,\"faces\":%d,\"attributes\":%s,\"textures\":%s,"
	    "\"materials\":%zu,\"material_textures\":%s,\"face_colours\":%s,"
	    "\"vertex_colours\":%s,\"wedge_uvs\":%s,\"vertex_uvs\":%s,\"texture_indices\":%s,"
	    "\"qualities\":%s,\"normal_length_error\":%.3g,\"distinct_normals\":%zu,\"face_materials\":"
	    "%s}\n",
	    m.vn, m.fn, attributes.c_str(), list(m.textures, str).c_str(), info.materials.size(),
	    list(mapKd, str).c_str(), list(faceColours, colour).c_str(),
	    list(vertexColours, colour).c_str(), list(wedgeUV, uv).c_str(), list(vertexUV, uv).c_str(),
	    list(texIndex, [](int i) { return std::to_string(i); }).c_str(),
	    list(quality, qual).c_str(), normalError, normals.size(),
	    list(faceMaterials, [](const std::pair<std::tuple<int, int, int, int>, std::string> &fm) {
		    return "[" + colour(fm.first) + "," + str(fm.second) + "]";
	    }).c_str());
	return 0;
}
