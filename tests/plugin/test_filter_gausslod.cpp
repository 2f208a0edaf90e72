// The GaussLOD MeshLab plugin, loaded from its .so the way MeshLab loads it (QPluginLoader, IID
// check), applied to real meshes in a MeshDocument, with no GUI and no display.
//
// Paths come from CMake: GAUSSLOD_PLUGIN_PATH (the built .so), GAUSSLOD_DATA_DIR (real models),
// GAUSSLOD_DEFAULT_SCRIPT (meshlab_scripts/gausslod_default.mlx).

#include "filter_fixture.h"

TEST_F(GaussLodPlugin, declares_itself_as_a_single_mesh_remeshing_filter)
{
	EXPECT_EQ(filter->getClass(action), MeshFilterInterface::Remeshing);
	EXPECT_EQ(filter->filterArity(action), MeshFilterInterface::SINGLE_MESH);
	EXPECT_EQ(filter->getPreConditions(action), int(MeshModel::MM_FACENUMBER));
	EXPECT_EQ(filter->postCondition(action), int(MeshModel::MM_NONE));
	EXPECT_TRUE(filter->filterInfo(action).contains("Gauss Sphere"));

	MeshDocument md;
	loadOffLayer(md, dataFile("cow.off"));
	const RichParameterList par = defaults(md);
	const QStringList expected = {
	    "maxLevel",         "levelsBy",         "levelTargets",    "outputLevels",   "featureAngle",
	    "straightenTol",    "mergeDist",        "maxDistance",     "distanceGrowth", "normalLimit",
	    "acrossCells",      "placeVertices",    "certifyDistance", "weldVertices",   "weldDistance",
	    "keepMaterials",    "keepSeams",        "maxTexError",     "completeChain",  "selectedOnly",
	    "colourSuperfaces", "overwriteColours", "fauxEdges"};
	EXPECT_EQ(par.size(), unsigned(expected.size()));
	for (const QString &name : expected)
		EXPECT_TRUE(par.hasParameter(name)) << qUtf8Printable(name);
	EXPECT_EQ(par.getInt("maxLevel"), 5);
	EXPECT_EQ(par.getString("outputLevels"), "all");
	EXPECT_EQ(par.getEnum("levelsBy"), 0); // (the paper's angle levels)
	EXPECT_EQ(par.getString("levelTargets"), "50%,25%,10%,5%,2%");
	EXPECT_TRUE(par.getBool("completeChain"));
	EXPECT_TRUE(par.getBool("certifyDistance"));
	EXPECT_FLOAT_EQ(par.getFloat("featureAngle"), 30.0f);
	const float diag = md.mm()->cm.bbox.Diag();
	EXPECT_NEAR(par.getAbsPerc("straightenTol"), 0.005f * diag, 1e-6f * diag);
	EXPECT_NEAR(par.getAbsPerc("mergeDist"), 0.0025f * diag, 1e-6f * diag);
	EXPECT_NEAR(par.getAbsPerc("maxDistance"), 0.0002f * diag, 1e-6f * diag);
	EXPECT_FLOAT_EQ(par.getFloat("distanceGrowth"), 2.0f);
	EXPECT_FLOAT_EQ(par.getFloat("normalLimit"), 1.0f);
	EXPECT_TRUE(par.getBool("acrossCells"));
	EXPECT_TRUE(par.getBool("placeVertices"));
	EXPECT_TRUE(par.getBool("colourSuperfaces"));
	EXPECT_TRUE(par.getBool("fauxEdges"));
	EXPECT_TRUE(par.getBool("keepMaterials"));
	EXPECT_TRUE(par.getBool("keepSeams"));
	EXPECT_FLOAT_EQ(par.getFloat("maxTexError"), 1.0f / 2048);
	EXPECT_FALSE(par.getBool("selectedOnly"));
	EXPECT_FALSE(par.getBool("overwriteColours"));
}

TEST_F(GaussLodPlugin, cow_with_defaults_gets_one_new_layer_per_level_and_stays_untouched)
{
	MeshDocument md;
	MeshModel *input = loadOffLayer(md, dataFile("cow.off"));
	ASSERT_GT(input->cm.fn, 5000);
	const LayerSnapshot before(*input);

	ASSERT_TRUE(apply(md, defaults(md))) << qUtf8Printable(filter->errorMsg());

	EXPECT_TRUE(LayerSnapshot(*input) == before) << "the input layer was modified";
	ASSERT_EQ(md.size(), 1 + 5);
	EXPECT_EQ(md.meshList.at(0), input);

	long finerFaces = input->cm.fn;
	for (int i = 1; i <= 5; ++i) {
		const MeshModel *lm = md.meshList.at(i);
		ParsedLabel label;
		ASSERT_TRUE(parseLabel(lm->label(), label)) << qUtf8Printable(lm->label());
		const int level = 5 - i; // finest first
		EXPECT_EQ(label.base, "cow");
		EXPECT_EQ(label.level, level);
		EXPECT_EQ(label.faces, lm->cm.fn) << qUtf8Printable(lm->label());
		// (a level continued by collapses to a real step does not keep its cells' bound)
		EXPECT_TRUE(label.bound.isEmpty() || label.bound == paperBound(level))
		    << qUtf8Printable(label.bound);
		EXPECT_GT(label.distancePct, 0.0) << "the default tolerance gives a distance bound";
		EXPECT_GT(lm->cm.fn, 0);
		EXPECT_LE(lm->cm.fn, finerFaces) << "LOD" << level << " has more faces than the finer one";
		EXPECT_LE(lm->cm.vn, input->cm.vn);
		EXPECT_TRUE(lm->hasDataMask(MeshModel::MM_FACECOLOR)) << "colourSuperfaces is on";
		EXPECT_TRUE(lm->fullName().isEmpty());
		finerFaces = lm->cm.fn;
	}
	EXPECT_LT(md.meshList.at(5)->cm.fn, input->cm.fn) << "the coarsest level merged nothing";
	EXPECT_TRUE(hasFauxEdge(md.meshList.at(5)->cm)) << "no superface interior marked faux";
	EXPECT_EQ(md.mm(), md.meshList.at(5)) << "the current layer is not the coarsest level";

	const QStringList lines = logLines();
	for (int level = 0; level < 5; ++level) {
		const QRegularExpression levelLine(
		    QString("^LOD%1 .* faces, .* vertices, .* superfaces, .* fallbacks, .* retriangulated; "
		            "normal deviation max .* deg, mean .* deg; .* s")
		        .arg(level));
		EXPECT_EQ(lines.filter(levelLine).size(), 1) << qUtf8Printable(lines.join("\n"));
	}
	EXPECT_EQ(lines.filter("5 layer(s) added").size(), 1) << qUtf8Printable(lines.join("\n"));
}

TEST_F(GaussLodPlugin, output_levels_selects_the_layers_and_options_are_honoured)
{
	MeshDocument md;
	MeshModel *input = loadOffLayer(md, dataFile("fandisk.off"));
	const LayerSnapshot before(*input);
	RichParameterList par = defaults(md);
	par.setValue("maxLevel", IntValue(3));
	par.setValue("outputLevels", StringValue(" 2, 0 "));
	par.setValue("colourSuperfaces", BoolValue(false));
	par.setValue("fauxEdges", BoolValue(false));

	ASSERT_TRUE(apply(md, par)) << qUtf8Printable(filter->errorMsg());
	EXPECT_TRUE(LayerSnapshot(*input) == before);
	ASSERT_EQ(md.size(), 3);
	ParsedLabel fine, coarse;
	ASSERT_TRUE(parseLabel(md.meshList.at(1)->label(), fine));
	ASSERT_TRUE(parseLabel(md.meshList.at(2)->label(), coarse));
	EXPECT_EQ(fine.base, "fandisk");
	EXPECT_EQ(fine.level, 2);
	EXPECT_EQ(coarse.level, 0);
	EXPECT_LE(md.meshList.at(2)->cm.fn, md.meshList.at(1)->cm.fn);
	EXPECT_EQ(md.mm(), md.meshList.at(2));
	for (int i = 1; i <= 2; ++i) {
		EXPECT_FALSE(md.meshList.at(i)->hasDataMask(MeshModel::MM_FACECOLOR));
		EXPECT_FALSE(hasFauxEdge(md.meshList.at(i)->cm));
	}
}

TEST_F(GaussLodPlugin, merging_across_cell_borders_only_removes_faces)
{
	// off = the paper's superfaces: the finest level of the noisy-free fandisk keeps the splits
	// that cell borders cut through its curved patches; on merges them within the bound
	int faces[2];
	for (int across = 0; across < 2; ++across) {
		MeshDocument md;
		MeshModel *input = loadOffLayer(md, dataFile("fandisk.off"));
		const LayerSnapshot before(*input);
		RichParameterList par = defaults(md);
		par.setValue("maxLevel", IntValue(3));
		par.setValue("outputLevels", StringValue("2"));
		par.setValue("acrossCells", BoolValue(across == 1));
		ASSERT_TRUE(apply(md, par)) << qUtf8Printable(filter->errorMsg());
		EXPECT_TRUE(LayerSnapshot(*input) == before);
		ASSERT_EQ(md.size(), 2);
		faces[across] = md.meshList.at(1)->cm.fn;
	}
	EXPECT_LT(faces[1], faces[0]);
	EXPECT_GT(faces[1], 12); // curved patches stay curved
}

TEST_F(GaussLodPlugin, mesh_without_vertices_or_faces_is_rejected)
{
	MeshDocument md;
	md.addNewMesh("", "empty", true);
	expectRejected(md, defaults(md), "empty mesh");
}

TEST_F(GaussLodPlugin, point_cloud_is_rejected)
{
	MeshDocument md;
	MeshModel *mm = md.addNewMesh("", "points.ply", true);
	auto vi = vcg::tri::Allocator<CMeshO>::AddVertices(mm->cm, 4);
	vi++->P() = Point3m(0, 0, 0);
	vi++->P() = Point3m(1, 0, 0);
	vi++->P() = Point3m(0, 1, 0);
	vi->P() = Point3m(0, 0, 1);
	mm->UpdateBoxAndNormals();
	expectRejected(md, defaults(md), "point cloud");
	EXPECT_TRUE(filter->errorMsg().contains("no faces")) << qUtf8Printable(filter->errorMsg());
}

TEST_F(GaussLodPlugin, out_of_range_parameters_are_rejected)
{
	MeshDocument md;
	loadOffLayer(md, dataFile("cow.off"));
	const std::vector<std::pair<const char *, std::shared_ptr<Value>>> cases = {
	    {"maxLevel", std::make_shared<IntValue>(0)},
	    {"maxLevel", std::make_shared<IntValue>(9)},
	    {"outputLevels", std::make_shared<StringValue>("5")},
	    {"outputLevels", std::make_shared<StringValue>("1,x")},
	    {"outputLevels", std::make_shared<StringValue>("")},
	    {"levelTargets", std::make_shared<StringValue>("")},
	    {"levelTargets", std::make_shared<StringValue>("150%")},
	    {"levelTargets", std::make_shared<StringValue>("50%,50%")},
	    {"levelTargets", std::make_shared<StringValue>("1,2,3,4,5,6,7,8,9")},
	    {"levelTargets", std::make_shared<StringValue>("abc")},
	    {"featureAngle", std::make_shared<FloatValue>(-1.0f)},
	    {"featureAngle", std::make_shared<FloatValue>(181.0f)},
	    {"straightenTol", std::make_shared<AbsPercValue>(-0.1f)},
	    {"mergeDist", std::make_shared<AbsPercValue>(-0.1f)},
	    {"maxDistance", std::make_shared<AbsPercValue>(-0.1f)},
	    {"normalLimit", std::make_shared<FloatValue>(-1.0f)},
	};
	for (const auto &c : cases) {
		RichParameterList par = defaults(md);
		par.setValue(c.first, *c.second);
		if (std::string(c.first) == "levelTargets") // (the list of face budgets)
			par.setValue("levelsBy", EnumValue(1));
		expectRejected(md, par, c.first);
	}
}

TEST_F(GaussLodPlugin, engine_error_is_reported_and_adds_no_layer)
{
	MeshDocument md;
	MeshModel *mm = md.addNewMesh("", "nan.ply", true);
	auto vi = vcg::tri::Allocator<CMeshO>::AddVertices(mm->cm, 3);
	vi[0].P() = Point3m(0, 0, 0);
	vi[1].P() = Point3m(1, 0, 0);
	vi[2].P() = Point3m(0, std::numeric_limits<float>::quiet_NaN(), 0);
	vcg::tri::Allocator<CMeshO>::AddFace(mm->cm, &mm->cm.vert[0], &mm->cm.vert[1], &mm->cm.vert[2]);
	RichParameterList par = defaults(md);
	par.setValue("straightenTol", AbsPercValue(0.0f)); // the NaN box makes the defaults NaN too
	par.setValue("mergeDist", AbsPercValue(0.0f));
	expectRejected(md, par, "non-finite coordinates");
	EXPECT_TRUE(filter->errorMsg().contains("non-finite")) << qUtf8Printable(filter->errorMsg());
}

bool progressCalls = false;
bool cancellingCallback(const int, const char *)
{
	progressCalls = true;
	return false;
}

TEST_F(GaussLodPlugin, cancelling_through_the_progress_callback_adds_no_layer)
{
	MeshDocument md;
	MeshModel *input = loadOffLayer(md, dataFile("cow.off"));
	const LayerSnapshot before(*input);
	progressCalls = false;
	EXPECT_FALSE(filter->applyFilter(action, md, defaults(md), cancellingCallback));
	EXPECT_TRUE(progressCalls) << "the progress callback was never called";
	EXPECT_TRUE(filter->errorMsg().contains("cancel")) << qUtf8Printable(filter->errorMsg());
	EXPECT_EQ(md.size(), 1);
	EXPECT_TRUE(LayerSnapshot(*input) == before);
}

/// What meshlabserver does with a script entry: the filter's defaults for the current mesh,
/// overridden by the parameters the script lists.
TEST_F(GaussLodPlugin, a_distance_tolerance_keeps_more_faces_where_levels_would_move_the_surface)
{
	MeshDocument free, bounded;
	loadOffLayer(free, dataFile("cow.off"));
	MeshModel *input = loadOffLayer(bounded, dataFile("cow.off"));
	const LayerSnapshot before(*input);
	RichParameterList normalsOnly = defaults(free);
	normalsOnly.setValue("maxDistance", AbsPercValue(0.0f)); // (the paper)
	normalsOnly.setValue("completeChain", BoolValue(false)); // (the superface levels: DESIGN 51)
	ASSERT_TRUE(apply(free, normalsOnly));
	RichParameterList par = defaults(bounded);
	const float diag = bounded.mm()->cm.bbox.Diag();
	par.setValue("maxDistance", AbsPercValue(0.001f * diag));
	par.setValue("distanceGrowth", FloatValue(1.0f)); // (0.1 % at every level)
	par.setValue("completeChain", BoolValue(false));
	ASSERT_TRUE(apply(bounded, par)) << qUtf8Printable(filter->errorMsg());
	EXPECT_TRUE(LayerSnapshot(*input) == before);
	ASSERT_EQ(free.size(), bounded.size());
	for (int i = 1; i < bounded.size(); ++i)
		EXPECT_GE(bounded.meshList.at(i)->cm.fn, free.meshList.at(i)->cm.fn) << i;
	// the coarsest level flattens the cow by ~2.5 % of its diagonal without the tolerance
	EXPECT_GT(bounded.meshList.back()->cm.fn, free.meshList.back()->cm.fn);
	// each level's log line gives its distance bound: the check keeps removed vertices within the
	// tolerance (0.1 %), the bound adds the pockets along straightened borders (DESIGN 23)
	const QStringList lines = logLines();
	const QRegularExpression bound(
	    "^LOD[0-4] .*; distance to the input at most ([0-9.]+) % of the diagonal");
	int seen = 0;
	for (const QString &line : lines) {
		const QRegularExpressionMatch m = bound.match(line);
		if (!m.hasMatch())
			continue;
		++seen;
		EXPECT_LE(m.captured(1).toDouble(), 3 * 0.1) << qUtf8Printable(line);
		EXPECT_GT(m.captured(1).toDouble(), 0.0) << qUtf8Printable(line);
	}
	EXPECT_EQ(seen, 5) << qUtf8Printable(lines.join("\n"));
}

TEST_F(GaussLodPlugin, default_script_runs_in_process_like_meshlabserver)
{
	FilterScript script;
	ASSERT_TRUE(script.open(GAUSSLOD_DEFAULT_SCRIPT));
	ASSERT_EQ(script.size(), 1);
	ASSERT_EQ(script.front().filterName(), kFilterName);

	MeshDocument md;
	MeshModel *input = loadOffLayer(md, dataFile("cow.off"));
	const LayerSnapshot before(*input);
	RichParameterList required = defaults(md);
	const RichParameterList &listed = script.front().second;
	ASSERT_EQ(listed.size(), required.size()) << "the script must list every parameter";
	RichParameterList par;
	for (const RichParameter &rp : required) {
		ASSERT_TRUE(listed.hasParameter(rp.name())) << qUtf8Printable(rp.name());
		const RichParameter &fromScript = listed.getParameterByName(rp.name());
		EXPECT_EQ(fromScript.stringType(), rp.stringType()) << qUtf8Printable(rp.name());
		par.addParam(fromScript);
	}
	// the script's AbsPerc range is 0..100, so its values are percentages of this mesh's diagonal;
	// the defaults are the same percentages, so both runs must give the same layers
	ASSERT_TRUE(apply(md, par)) << qUtf8Printable(filter->errorMsg());
	EXPECT_TRUE(LayerSnapshot(*input) == before);
	ASSERT_EQ(md.size(), 6);
	EXPECT_EQ(md.mm(), md.meshList.at(5));

	MeshDocument md2;
	loadOffLayer(md2, dataFile("cow.off"));
	ASSERT_TRUE(apply(md2, defaults(md2))) << qUtf8Printable(filter->errorMsg());
	ASSERT_EQ(md2.size(), 6);
	for (int i = 1; i <= 5; ++i) {
		EXPECT_EQ(md.meshList.at(i)->label(), md2.meshList.at(i)->label());
		EXPECT_EQ(md.meshList.at(i)->cm.vn, md2.meshList.at(i)->cm.vn);
	}
}

// Levels by target (issue #17): one layer per face budget, each within it, the log saying the
// target, whether it was reached and the tolerance used; layer names as in angle mode.
TEST_F(GaussLodPlugin, levels_by_face_budget_make_one_layer_per_budget_within_it)
{
	MeshDocument md;
	MeshModel *input = loadOffLayer(md, dataFile("fandisk.off"));
	const LayerSnapshot before(*input);
	RichParameterList par = defaults(md);
	par.setValue("levelsBy", EnumValue(1)); // (face budgets)
	par.setValue("levelTargets", StringValue("10%, 50%,25%"));
	ASSERT_TRUE(apply(md, par)) << qUtf8Printable(filter->errorMsg());
	EXPECT_TRUE(LayerSnapshot(*input) == before);
	ASSERT_EQ(md.size(), 1 + 3); // (maxLevel 5 is replaced by the 3 targets)
	const int fn = input->cm.fn;
	const QStringList lines = logLines();
	for (int i = 1; i <= 3; ++i) {
		const MeshModel *lm = md.meshList.at(i);
		ParsedLabel label;
		ASSERT_TRUE(parseLabel(lm->label(), label)) << qUtf8Printable(lm->label());
		const int level = 3 - i;
		const int budget = fn * (level == 2 ? 50 : level == 1 ? 25 : 10) / 100;
		EXPECT_EQ(label.level, level);
		EXPECT_EQ(label.faces, lm->cm.fn);
		EXPECT_LE(lm->cm.fn, budget) << "LOD" << level;
		EXPECT_GT(lm->cm.fn, budget * 95 / 100) << "LOD" << level;
		const QRegularExpression line(
		    QString("^LOD%1 .*; target %2 faces reached, distance tolerance [0-9.e+-]+ % of the "
		            "diagonal \\([0-9]+ builds?\\)$")
		        .arg(level)
		        .arg(QLocale(QLocale::English).toString(budget)));
		EXPECT_EQ(lines.filter(line).size(), 1) << qUtf8Printable(lines.join("\n"));
	}
	EXPECT_EQ(lines.filter("Levels by faces:50%,25%,10%: 3 levels").size(), 1)
	    << qUtf8Printable(lines.join("\n"));
}

// A budget the superfaces cannot reach (the cow's curved surface keeps more than half its faces
// at the coarsest level's bound) is reached by collapses (DESIGN 51); one below a closed surface's
// least (a tetrahedron's 4 faces) is as close as it gets, and the log says so.
TEST_F(GaussLodPlugin, every_budget_is_reached_and_one_out_of_reach_is_reported)
{
	MeshDocument md;
	loadOffLayer(md, dataFile("cow.off"));
	RichParameterList par = defaults(md);
	par.setValue("levelsBy", EnumValue(1));
	par.setValue("levelTargets", StringValue("10%,0.05%")); // (580 and 2 faces)
	ASSERT_TRUE(apply(md, par)) << qUtf8Printable(filter->errorMsg());
	ASSERT_EQ(md.size(), 3);
	EXPECT_LE(md.meshList.at(1)->cm.fn, 580);
	EXPECT_EQ(md.meshList.at(2)->cm.fn, 4);
	const QStringList lines = logLines();
	EXPECT_EQ(lines
	              .filter(QRegularExpression("^LOD1 .*continued from LOD2 by [0-9,]+ edge "
	                                         "collapses.*; target 580 faces reached"))
	              .size(),
	          1)
	    << qUtf8Printable(lines.join("\n"));
	EXPECT_EQ(lines
	              .filter(QRegularExpression("^LOD0 .*; target 2 faces NOT reached \\(4 faces: "
	                                         "the least a mesh of its topology can have "
	                                         "\\(closed\\)\\)"))
	              .size(),
	          1)
	    << qUtf8Printable(lines.join("\n"));
}

// A script written when "Levels by" was text (levelsBy "faces:10%", no levelTargets): read as
// that text.
TEST_F(GaussLodPlugin, a_script_with_levels_by_as_text_is_read_as_before)
{
	MeshDocument md;
	loadOffLayer(md, dataFile("fandisk.off"));
	RichParameterList old;
	for (const RichParameter &rp : defaults(md))
		if (rp.name() != "levelsBy" && rp.name() != "levelTargets")
			old.addParam(rp);
	old.addParam(RichString("levelsBy", "faces:10%", "Levels by", ""));
	ASSERT_TRUE(apply(md, old)) << qUtf8Printable(filter->errorMsg());
	ASSERT_EQ(md.size(), 2);
	EXPECT_LE(md.meshList.at(1)->cm.fn, 1294);
}

// A script written before "Levels by" existed (no such parameter): levels by angle, as before.
TEST_F(GaussLodPlugin, a_script_without_levels_by_gives_the_angle_levels)
{
	MeshDocument md, md2;
	loadOffLayer(md, dataFile("fandisk.off"));
	loadOffLayer(md2, dataFile("fandisk.off"));
	RichParameterList old;
	for (const RichParameter &rp : defaults(md))
		if (rp.name() != "levelsBy" && rp.name() != "levelTargets")
			old.addParam(rp);
	ASSERT_FALSE(old.hasParameter("levelsBy"));
	ASSERT_TRUE(apply(md, old)) << qUtf8Printable(filter->errorMsg());
	ASSERT_TRUE(apply(md2, defaults(md2))) << qUtf8Printable(filter->errorMsg());
	ASSERT_EQ(md.size(), 6);
	ASSERT_EQ(md2.size(), 6);
	for (int i = 1; i <= 5; ++i)
		EXPECT_EQ(md.meshList.at(i)->label(), md2.meshList.at(i)->label());
}

int main(int argc, char **argv)
{
	QCoreApplication app(argc, argv);
	::testing::InitGoogleTest(&argc, argv);
	return RUN_ALL_TESTS();
}

namespace {
/// Geometry of a layer only: positions and face vertex indices (no colour, no flags).
std::pair<std::vector<float>, std::vector<int>> geometry(const CMeshO &m)
{
	std::pair<std::vector<float>, std::vector<int>> g;
	for (const auto &v : m.vert)
		for (int k = 0; k < 3; ++k)
			g.first.push_back(v.cP()[k]);
	for (const auto &f : m.face)
		for (int k = 0; k < 3; ++k)
			g.second.push_back(int(vcg::tri::Index(m, f.cV(k))));
	return g;
}
} // namespace

TEST_F(GaussLodPlugin, colour_and_faux_options_change_what_they_claim_and_nothing_else)
{
	MeshDocument on, off;
	loadOffLayer(on, dataFile("fandisk.off"));
	loadOffLayer(off, dataFile("fandisk.off"));
	ASSERT_TRUE(apply(on, defaults(on)));
	RichParameterList par = defaults(off);
	par.setValue("colourSuperfaces", BoolValue(false));
	par.setValue("fauxEdges", BoolValue(false));
	ASSERT_TRUE(apply(off, par));
	ASSERT_EQ(on.size(), off.size());
	for (int i = 1; i < on.size(); ++i) {
		const CMeshO &a = on.meshList.at(i)->cm, &b = off.meshList.at(i)->cm;
		EXPECT_TRUE(geometry(a) == geometry(b))
		    << "layer " << i << ": the options changed geometry";
		EXPECT_FALSE(hasFauxEdge(b));
		// faux edges lie inside a superface: both faces across one have the same colour; a
		// superface border (not faux) separates two colours
		on.meshList.at(i)->updateDataMask(MeshModel::MM_FACEFACETOPO);
		CMeshO &mutableA = on.meshList.at(i)->cm;
		size_t faux = 0, borders = 0, borderSameColour = 0;
		for (auto &f : mutableA.face)
			for (int k = 0; k < 3; ++k) {
				const auto *g = f.cFFp(k);
				if (g == &f)
					continue;
				if (f.IsF(k)) {
					++faux;
					EXPECT_EQ(f.cC(), g->cC()) << "a faux edge between two superfaces";
				} else {
					++borders;
					borderSameColour += f.cC() == g->cC();
				}
			}
		EXPECT_GT(faux, 0u);
		EXPECT_LT(borderSameColour, borders / 20 + 1) << "neighbouring superfaces share colours";
	}
}

TEST_F(GaussLodPlugin, a_looser_normal_limit_simplifies_at_least_as_much)
{
	MeshDocument strict, loose;
	loadOffLayer(strict, dataFile("cow.off"));
	loadOffLayer(loose, dataFile("cow.off"));
	RichParameterList superfaces = defaults(strict); // (the superface levels: DESIGN 51)
	superfaces.setValue("completeChain", BoolValue(false));
	ASSERT_TRUE(apply(strict, superfaces));
	RichParameterList par = superfaces;
	par.setValue("normalLimit", FloatValue(0.0f)); // no limit
	ASSERT_TRUE(apply(loose, par));
	// the limit (x the level bound) matters where the bound is below 90 deg: levels 4..1
	long strictFaces = 0, looseFaces = 0;
	for (int i = 1; i < strict.size(); ++i) {
		EXPECT_LE(loose.meshList.at(i)->cm.fn, strict.meshList.at(i)->cm.fn);
		strictFaces += strict.meshList.at(i)->cm.fn;
		looseFaces += loose.meshList.at(i)->cm.fn;
	}
	EXPECT_LT(looseFaces, strictFaces);
}
