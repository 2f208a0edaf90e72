// OBJ import: LoadMask, the input check, VCG's Open with its index fix, texture names made local.

#include "io_obj.h"

#include <gausslod_io/obj_import.h>

GAUSSLOD_FIX_VCG_OBJ_INDICES(CMeshO)

#include <QDir>
#include <QFile>
#include <QFileInfo>

#include <string>

namespace {

using ObjImporter = vcg::tri::io::ImporterOBJ<CMeshO>;
static_assert(gausslod::obj::IndexFixFor<CMeshO>::value, "ImporterOBJ<CMeshO> needs the index fix");

/// Switches the current directory for a scope: VCG opens mtllib files from the current directory,
/// and texture names stay relative to the OBJ file, as MeshLab's own loader leaves them.
class CurrentDirectory {
public:
	explicit CurrentDirectory(const QString &dir) : previous_(QDir::currentPath())
	{
		changed_ = QDir::setCurrent(dir);
	}
	~CurrentDirectory()
	{
		if (changed_)
			QDir::setCurrent(previous_);
	}
	bool changed() const { return changed_; }

private:
	QString previous_;
	bool changed_ = false;
};

/// Files exported on Windows name their textures like ".\wood.jpg": where that file does not exist
/// and the name with '/' does, the texture gets the name that opens.
void useLocalTextureNames(std::vector<std::string> &textures)
{
	for (std::string &name : textures) {
		if (name.find('\\') == std::string::npos || QFile::exists(QFile::decodeName(name.c_str())))
			continue;
		std::string local = name;
		for (char &c : local)
			if (c == '\\')
				c = '/';
		if (QFile::exists(QFile::decodeName(local.c_str())))
			name = local;
	}
}

} // namespace

QString GaussLodObjIOPlugin::pluginName() const { return "GaussLodObjIO"; }

QList<MeshIOInterface::Format> GaussLodObjIOPlugin::importFormats() const
{
	return {Format("Alias Wavefront Object", tr("OBJ"))};
}

QList<MeshIOInterface::Format> GaussLodObjIOPlugin::exportFormats() const
{
	return {}; // io_base's OBJ export works
}

void GaussLodObjIOPlugin::GetExportMaskCapability(QString &, int &capability,
                                                  int &defaultBits) const
{
	capability = defaultBits = 0;
}

bool GaussLodObjIOPlugin::open(const QString &format, const QString &fileName, MeshModel &m,
                               int &mask, const RichParameterList &, vcg::CallBackPos *cb,
                               QWidget *)
{
	const QString errorFormat =
	    "Error encountered while loading file:\n\"%1\"\n\nError details: %2";
	auto fail = [&](const QString &why) {
		errorMessage = errorFormat.arg(fileName, why);
		// meshlabserver does not print errorMessage: say it on stderr too
		qWarning("GaussLOD OBJ import: %s: %s", qUtf8Printable(fileName), qUtf8Printable(why));
		return false;
	};
	if (format.toUpper() != "OBJ")
		return fail("GaussLOD's OBJ plugin does not read " + format + " files");
	const QFileInfo file(fileName); // MeshLab passes a name relative to the current directory
	if (!file.isFile())
		return fail("File does not exist");
	if (!file.isReadable())
		return fail("File is not readable");
	if (file.size() == 0)
		return fail("The file is empty");

	const CurrentDirectory inFileFolder(file.absolutePath());
	if (!inFileFolder.changed())
		return fail("cannot enter the file's folder " + file.absolutePath());
	const std::string path = QFile::encodeName(file.absoluteFilePath()).toStdString();

	mask = 0;
	ObjImporter::Info oi;
	oi.cb = cb;
	if (!ObjImporter::LoadMask(path.c_str(), oi))
		return fail(ObjImporter::ErrorMsg(ObjImporter::E_CANTOPEN));
	std::string problem;
	if (!gausslod::obj::checkObjForVcg<CMeshO>(path.c_str(), oi, problem))
		return fail("not a Wavefront OBJ file MeshLab can read: " +
		            QString::fromStdString(problem));

	m.Enable(oi.mask);
	const int result = ObjImporter::Open(m.cm, path.c_str(), oi);
	if (ObjImporter::ErrorCritical(result)) {
		m.cm.Clear();
		return fail(ObjImporter::ErrorMsg(result));
	}
	// a non-critical error is kept as io_base keeps it: MeshLab shows it and loads the mesh
	if (result != ObjImporter::E_NOERROR)
		errorMessage = errorFormat.arg(fileName, ObjImporter::ErrorMsg(result));
	useLocalTextureNames(m.cm.textures);
	m.Enable(oi.mask);
	gausslod::obj::settleUnusedVertexTexCoords(m.cm, oi.mask);
	mask = oi.mask;
	return true;
}

bool GaussLodObjIOPlugin::save(const QString &format, const QString &, MeshModel &, const int,
                               const RichParameterList &, vcg::CallBackPos *, QWidget *)
{
	errorMessage = "GaussLOD's OBJ plugin does not save " + format + " files";
	return false;
}

MESHLAB_PLUGIN_NAME_EXPORTER(GaussLodObjIOPlugin)
