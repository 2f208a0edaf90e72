// The parameters' one source of truth: what the filter's dialog and the tool's options are built
// from agrees with Params{} (so a bare call gives the filter's levels), and validation names the
// parameter that is out of range.
#include "gausslod/gausslod.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <string>

using namespace gausslod;

TEST(Params, the_specs_defaults_are_params_defaults_and_valid)
{
	const Params d;
	std::set<std::string> names;
	for (const ParamSpec &s : paramSpecs()) {
		EXPECT_TRUE(names.insert(s.name).second) << s.name;
		EXPECT_EQ(findParam(s.name), &s);
		if (s.kind != ParamKind::LevelList && s.kind != ParamKind::LevelTargets)
			EXPECT_EQ(getParam(d, s), s.defaultValue) << s.name;
	}
	EXPECT_EQ(validateParams(d), "");
	// the filter's defaults, as fractions of the diagonal
	EXPECT_EQ(d.straightenTol, 0.005);
	EXPECT_EQ(d.mergeDist, 0.0025);
	EXPECT_EQ(findParam("deviationFactor"), nullptr); // one name per parameter
}

TEST(Params, an_out_of_range_value_is_refused_by_its_name)
{
	for (const ParamSpec &s : paramSpecs()) {
		if (s.kind == ParamKind::LevelList || s.kind == ParamKind::LevelTargets ||
		    s.kind == ParamKind::Flag)
			continue;
		for (const double bad : {s.min - 1, std::isfinite(s.max) ? s.max + 1 : NAN, double(NAN)}) {
			Params p;
			setParam(p, s, bad);
			const std::string e = validateParams(p);
			EXPECT_NE(e.find(std::string("(") + s.name + ")"), std::string::npos)
			    << s.name << ": " << e;
		}
		Params p;
		setParam(p, s, s.max == HUGE_VAL ? s.min + 1 : s.openRange ? 0.5 * (s.min + s.max) : s.max);
		EXPECT_EQ(validateParams(p), "") << s.name;
	}
	Params p;
	p.maxDistance = 1.2;
	EXPECT_NE(validateParams(p).find("120 %"), std::string::npos) << validateParams(p);
}

TEST(Params, output_levels_are_all_or_a_list_of_level_indices)
{
	uint32_t mask = 0;
	std::string error;
	EXPECT_TRUE(parseOutputLevels("all", 5, mask, error));
	EXPECT_EQ(mask, 31u);
	EXPECT_TRUE(parseOutputLevels(" ALL ", 3, mask, error));
	EXPECT_EQ(mask, 7u);
	EXPECT_TRUE(parseOutputLevels("0, 2", 5, mask, error));
	EXPECT_EQ(mask, 5u);
	for (const char *bad : {"5", "1,x", "", "-1", "1,,2"}) {
		EXPECT_FALSE(parseOutputLevels(bad, 5, mask, error)) << bad;
		EXPECT_NE(error.find("is not a level index"), std::string::npos) << error;
	}
}

TEST(Params, levels_by_reads_face_and_error_targets_in_level_order)
{
	Params p;
	std::string error;
	ASSERT_TRUE(parseLevelsBy(" faces: 10%, 50% ,25%", p, error)) << error;
	EXPECT_EQ(p.maxLevel, 3);
	EXPECT_TRUE(p.levelFacesRelative);
	EXPECT_EQ(p.levelFaces, (std::vector<double>{0.10, 0.25, 0.50}));
	EXPECT_TRUE(p.levelDistances.empty());
	EXPECT_EQ(validateParams(p), "");
	EXPECT_EQ(levelsByText(p), "faces:50%,25%,10%");
	ASSERT_TRUE(parseLevelsBy("FACES:5000,20000", p, error)) << error;
	EXPECT_EQ(p.maxLevel, 2);
	EXPECT_FALSE(p.levelFacesRelative);
	EXPECT_EQ(p.levelFaces, (std::vector<double>{5000, 20000}));
	EXPECT_EQ(levelsByText(p), "faces:20000,5000");
	ASSERT_TRUE(parseLevelsBy("error:0.01%,0.2%,0.05", p, error)) << error;
	EXPECT_EQ(p.maxLevel, 3);
	EXPECT_TRUE(p.levelFaces.empty());
	EXPECT_EQ(p.levelDistances, (std::vector<double>{0.002, 0.0005, 0.0001}));
	EXPECT_EQ(validateParams(p), "");
	EXPECT_EQ(levelsByText(p), "error:0.01%,0.05%,0.2%");
	// angle (or nothing): the paper's levels, the number of levels is maxLevel's again
	for (const char *angle : {"angle", "", " Angle "}) {
		Params q = p;
		q.maxLevel = 6;
		ASSERT_TRUE(parseLevelsBy(angle, q, error)) << angle;
		EXPECT_TRUE(q.levelFaces.empty() && q.levelDistances.empty());
		EXPECT_EQ(q.maxLevel, 6);
		EXPECT_EQ(levelsByText(q), "angle");
	}
}

TEST(Params, bad_levels_by_lists_are_refused_with_a_reason)
{
	const std::pair<const char *, const char *> bad[] = {
	    {"faces:", "needs a comma list"},
	    {"error:  ", "needs a comma list"},
	    {"faces", "is not a mode"},
	    {"angle:5", "is not a mode"},
	    {"vertices:50%", "is not a mode"},
	    {"faces:50%,abc", "'abc' is not a number"},
	    {"faces:50%,,25%", "'' is not a number"},
	    {"faces:50%%", "is not a number"},
	    {"faces:0%", "above 0"},
	    {"faces:-5", "above 0"},
	    {"error:0", "above 0"},
	    {"faces:150%", "at most 100%"},
	    {"error:101%", "at most 100%"},
	    {"faces:2.5", "whole number"},
	    {"faces:50%,1000", "not both"},
	    {"faces:1,2,3,4,5,6,7,8,9", "at most 8"},
	    {"faces:50%,25%,50%", "given twice"},
	    {"error:0.1%,0.1", "given twice"},
	    {"faces:nan", "is not a number"},
	    {"faces:inf", "is not a number"},
	};
	for (const auto &b : bad) {
		Params p;
		std::string error;
		EXPECT_FALSE(parseLevelsBy(b.first, p, error)) << b.first;
		EXPECT_NE(error.find(b.second), std::string::npos) << b.first << ": " << error;
		EXPECT_NE(error.find("(levelsBy)"), std::string::npos) << error;
		EXPECT_EQ(p.maxLevel, Params{}.maxLevel) << b.first; // unchanged
		EXPECT_TRUE(p.levelFaces.empty() && p.levelDistances.empty());
	}
	// set directly: validateParams checks what parseLevelsBy guarantees
	Params p;
	p.maxLevel = 2;
	p.levelFaces = {100, 50}; // fewest faces must be level 0's
	EXPECT_NE(validateParams(p).find("grow from level 0"), std::string::npos) << validateParams(p);
	p.levelFaces = {50, 100, 200};
	EXPECT_NE(validateParams(p).find("one per level"), std::string::npos);
	p.levelFaces = {50, 100};
	EXPECT_EQ(validateParams(p), "");
	p.levelDistances = {0.01, 0.001};
	EXPECT_NE(validateParams(p).find("not both"), std::string::npos);
	p.levelFaces.clear();
	EXPECT_EQ(validateParams(p), "");
	p.levelDistances = {0.01, 0.0};
	EXPECT_NE(validateParams(p).find("above 0"), std::string::npos);
	p.levelDistances.clear();
	p.levelFaces = {0.5, 1.5};
	p.levelFacesRelative = true;
	EXPECT_NE(validateParams(p).find("at most 100 %"), std::string::npos);
	// and buildLevels refuses it as a bad parameter
	const double pos[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
	const int32_t tri[3] = {0, 1, 2};
	MeshView m;
	m.positions = pos, m.vertexCount = 3, m.triangles = tri, m.faceCount = 1;
	const Result r = buildLevels(m, p);
	EXPECT_FALSE(r.ok);
	EXPECT_EQ(r.errorKind, ErrorKind::BadParameter);
}
