// menu_index PLUGIN_DIR "FILTER NAME"
// Prints the position (0-based) of a filter inside MeshLab's "Filters > Remeshing, Simplification
// and Reconstruction" submenu, computed the way MeshLab 2020.09 fills it
// (MainWindow::fillFilterMenu: every filter of PluginManager::stringFilterMap, in key order, whose
// class has the Remeshing bit). Exit status 1 (and a message) if the filter is not loaded or not in
// that submenu. The GUI test uses it to drive the menu with the keyboard; whether the entry it
// lands on really is the filter is then checked on the screen (the dialog that opens carries the
// filter's name).

#include <common/interfaces.h>
#include <common/mlexception.h>
#include <common/pluginmanager.h>

#include <QApplication>
#include <QDir>

#include <cstdio>

int main(int argc, char **argv)
{
	QApplication app(argc, argv);
	if (argc != 3) {
		std::fprintf(stderr, "usage: %s PLUGIN_DIR \"FILTER NAME\"\n", argv[0]);
		return 2;
	}
	const QString wanted = QString::fromUtf8(argv[2]);
	PluginManager pm;
	RichParameterList globals;
	try {
		pm.loadPlugins(globals, QDir(QString::fromUtf8(argv[1])));
	} catch (const MLException &e) {
		std::fprintf(stderr, "menu_index: loading plugins failed: %s\n", e.what());
		return 1;
	}
	if (!pm.stringFilterMap.contains(wanted)) {
		std::fprintf(stderr, "menu_index: no plugin in %s provides the filter '%s'\n", argv[1],
		             argv[2]);
		return 1;
	}
	int index = 0;
	for (auto it = pm.stringFilterMap.begin(); it != pm.stringFilterMap.end(); ++it) {
		MeshFilterInterface *filter = it.value();
		if (!(filter->getClass(filter->AC(it.key())) & MeshFilterInterface::Remeshing))
			continue;
		if (it.key() == wanted) {
			std::printf("%d\n", index);
			return 0;
		}
		++index;
	}
	std::fprintf(stderr, "menu_index: '%s' is not in the Remeshing submenu (wrong filter class)\n",
	             argv[2]);
	return 1;
}
