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
		if (s.kind != ParamKind::LevelList)
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
		if (s.kind == ParamKind::LevelList || s.kind == ParamKind::Flag)
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
