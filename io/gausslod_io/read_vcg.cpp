// importMesh and its VCG importers compiled once for the mesh types of the tools (io_mesh.h):
// import_mesh.h declares these instantiations extern, so its includers do not compile them again.
#include "import_mesh.h"

namespace gausslod {

template bool importMesh<IoMesh>(IoMesh &, const std::string &, ReadError &, ReadInfo *);
template bool importMesh<IoAttrMesh>(IoAttrMesh &, const std::string &, ReadError &, ReadInfo *);
template bool importMeshEither<IoMesh, IoAttrMesh>(IoMesh &, IoAttrMesh &, bool &,
                                                   const std::string &, int, ReadError &,
                                                   ReadInfo *, detail::FlatRead *);
namespace detail {
template bool readChecked<IoMesh>(IoMesh &, CheckedFile &, ReadError &, ReadInfo *);
template bool readChecked<IoAttrMesh>(IoAttrMesh &, CheckedFile &, ReadError &, ReadInfo *);
} // namespace detail

} // namespace gausslod
