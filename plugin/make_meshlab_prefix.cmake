# cmake -P script, run at build time: (re)makes a private MeshLab prefix that loads the built plugin.
#   PREFIX/bin/meshlab, PREFIX/bin/meshlabserver           copies (a symlink resolves to /usr/bin and
#                                                         MeshLab would load the system plugins)
#   PREFIX/lib/MULTIARCH/meshlab/libmeshlab-common.so      -> SYSTEM_LIBDIR/libmeshlab-common.so
#   PREFIX/lib/MULTIARCH/meshlab/plugins/*.so              -> every system plugin, PLUGIN and
#                                                         OBJ_PLUGIN (our OBJ importer)
# Inputs: PREFIX, MULTIARCH, SYSTEM_LIBDIR, SYSTEM_BINDIR, PLUGIN, OBJ_PLUGIN.
foreach(var PREFIX MULTIARCH SYSTEM_LIBDIR SYSTEM_BINDIR PLUGIN OBJ_PLUGIN)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "make_meshlab_prefix.cmake: ${var} is not set")
  endif()
endforeach()

set(libdir "${PREFIX}/lib/${MULTIARCH}/meshlab")
set(plugdir "${libdir}/plugins")
file(MAKE_DIRECTORY "${PREFIX}/bin" "${plugdir}")

foreach(exe meshlab meshlabserver)
  if(NOT EXISTS "${SYSTEM_BINDIR}/${exe}")
    message(FATAL_ERROR "${SYSTEM_BINDIR}/${exe} not found: install meshlab")
  endif()
  if(IS_SYMLINK "${PREFIX}/bin/${exe}")
    file(REMOVE "${PREFIX}/bin/${exe}")
  endif()
  execute_process(COMMAND ${CMAKE_COMMAND} -E copy_if_different
                          "${SYSTEM_BINDIR}/${exe}" "${PREFIX}/bin/${exe}"
                  RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "cannot copy ${SYSTEM_BINDIR}/${exe} into ${PREFIX}/bin")
  endif()
endforeach()

function(link_to target name)
  if(IS_SYMLINK "${name}")
    file(READ_SYMLINK "${name}" current)
    if(current STREQUAL target)
      return()
    endif()
  endif()
  file(REMOVE "${name}")
  file(CREATE_LINK "${target}" "${name}" SYMBOLIC)
endfunction()

link_to("${SYSTEM_LIBDIR}/libmeshlab-common.so" "${libdir}/libmeshlab-common.so")

# Start from a clean plugin list, so a plugin removed from the system does not linger here.
get_filename_component(ours "${PLUGIN}" NAME)
get_filename_component(ours_obj "${OBJ_PLUGIN}" NAME)
file(GLOB stale "${plugdir}/*")
foreach(f IN LISTS stale)
  get_filename_component(n "${f}" NAME)
  if(NOT n STREQUAL ours AND NOT n STREQUAL ours_obj)
    file(REMOVE "${f}")
  endif()
endforeach()
file(GLOB system_plugins "${SYSTEM_LIBDIR}/plugins/*.so")
foreach(p IN LISTS system_plugins)
  get_filename_component(n "${p}" NAME)
  # a system-wide installed copy of this plugin must not shadow the one just built
  if(NOT n STREQUAL ours AND NOT n STREQUAL ours_obj)
    link_to("${p}" "${plugdir}/${n}")
  endif()
endforeach()
link_to("${PLUGIN}" "${plugdir}/${ours}")
link_to("${OBJ_PLUGIN}" "${plugdir}/${ours_obj}")
