# find_package(cairn): imported targets cairn::cairn (shared), cairn::cairn_static,
# cairn::cairn_figure (figures, with cairo) and cairn::cairn_figure_static.
include(CMakeFindDependencyMacro)
find_dependency(Threads)
find_dependency(PkgConfig)
pkg_check_modules(JANSSON REQUIRED IMPORTED_TARGET jansson>=2.14)
pkg_check_modules(CAIRO REQUIRED IMPORTED_TARGET cairo)
include("${CMAKE_CURRENT_LIST_DIR}/cairnTargets.cmake")
