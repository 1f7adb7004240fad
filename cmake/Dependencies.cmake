# Every dependency comes from a Debian 12 package (tools/setup.sh installs them).
# How each is consumed, and why, is in ../shared/platform-notes.md.
find_package(PkgConfig REQUIRED)
find_package(Threads REQUIRED)
find_package(embree 3 CONFIG REQUIRED)          # target: embree
find_package(TBB CONFIG REQUIRED)               # target: TBB::tbb (never TBB::tbbbind_2_5)
find_package(glm CONFIG REQUIRED)               # target: glm::glm
find_package(TinyGLTF CONFIG REQUIRED)          # target: TinyGLTF::TinyGLTF (shared library)
find_package(nlohmann_json 3 CONFIG REQUIRED)   # target: nlohmann_json::nlohmann_json
find_package(hwy CONFIG REQUIRED)               # targets: hwy::hwy, hwy::hwy_contrib
find_package(CLI11 CONFIG REQUIRED)             # target: CLI11::CLI11 (keep in one source file)
# OpenImageIO's CMake config is broken on Debian 12: use pkg-config.
pkg_check_modules(OIIO REQUIRED IMPORTED_TARGET OpenImageIO)

# OpenSubdiv ships no usable CMake config: a small imported target of our own.
find_path(OPENSUBDIV_INCLUDE_DIR opensubdiv/version.h REQUIRED)
find_library(OPENSUBDIV_CPU_LIBRARY osdCPU REQUIRED)
add_library(epi_opensubdiv INTERFACE)
target_include_directories(epi_opensubdiv SYSTEM INTERFACE ${OPENSUBDIV_INCLUDE_DIR})
target_link_libraries(epi_opensubdiv INTERFACE ${OPENSUBDIV_CPU_LIBRARY})
add_library(epi::opensubdiv ALIAS epi_opensubdiv)

if(EPI_BUILD_TESTS)
  find_package(GTest CONFIG REQUIRED)
  include(GoogleTest)
endif()
if(EPI_BUILD_BENCH)
  find_package(benchmark CONFIG REQUIRED)
endif()
if(EPI_BUILD_GUI)
  find_package(glfw3 3.3 CONFIG REQUIRED)
  find_package(OpenGL REQUIRED)
  pkg_check_modules(IMGUI REQUIRED IMPORTED_TARGET imgui)
endif()
