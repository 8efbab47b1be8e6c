# Every third-party library is an installed Debian package (see README and cmake/run.sh).
find_package(Eigen3 3.3 REQUIRED NO_MODULE)
find_package(SDL2 REQUIRED)
find_package(pugixml REQUIRED)
find_package(CLI11 REQUIRED)
find_package(nlohmann_json 3 REQUIRED)
find_package(tomlplusplus REQUIRED)
find_package(PkgConfig REQUIRED)
pkg_check_modules(STB REQUIRED IMPORTED_TARGET stb)

# CGAL is used in exactly one translation unit (src/geom/triangulate.cpp).
set(CGAL_DO_NOT_WARN_ABOUT_CMAKE_BUILD_TYPE TRUE)
find_package(CGAL REQUIRED)

if(MARIONETTE_BUILD_TESTS)
  find_package(GTest REQUIRED)
endif()
if(MARIONETTE_BUILD_BENCH)
  find_package(benchmark REQUIRED)
endif()
