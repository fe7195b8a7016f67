# Every third-party package Acrolab uses is found here, once. All come from Debian 12's packages
# (scripts/install-deps.sh installs them); nothing is downloaded at configure or build time.

find_package(Eigen3 3.4 REQUIRED NO_MODULE)
find_package(Threads REQUIRED)
find_package(PkgConfig REQUIRED)

# Formatting, YAML, JSON and the command line (Debian's libfmt-dev, libyaml-cpp-dev,
# nlohmann-json3-dev, libcli11-dev).
find_package(fmt REQUIRED)
find_package(yaml-cpp REQUIRED)
find_package(nlohmann_json 3.10 REQUIRED)
find_package(CLI11 REQUIRED)

# toml++: camera calibrations in the Pose2Sim/Anipose format (analysis/vision only).
pkg_check_modules(TOMLPLUSPLUS REQUIRED IMPORTED_TARGET tomlplusplus)
# pugixml: Qualisys calibrations (analysis/vision) and OpenSim models (the OpenSim oracle test).
find_package(pugixml REQUIRED)

# OpenCV: camera calibration (analysis/vision only; board detection, calibrateCamera, solvePnP)
# and the camera tests' oracles. Debian 12 ships OpenCV's CMake config (and opencv4.pc) only in
# libopencv-dev, which depends on every module — contrib, and viz with VTK and Qt; the main job
# installs only the four modules it uses (libopencv-{core,imgproc,imgcodecs,calib3d}-dev), so they
# are found here by hand, as the imported target acro::opencv. ChArUco boards need the contrib
# module aruco (libopencv-contrib-dev, in the full install only): found when present, and without
# it a ChArUco board is refused with that reason (ACRO_HAVE_ARUCO).
find_path(ACRO_OPENCV_INCLUDE_DIR opencv2/calib3d.hpp PATH_SUFFIXES opencv4 REQUIRED)
add_library(acro::opencv INTERFACE IMPORTED)
target_include_directories(acro::opencv INTERFACE ${ACRO_OPENCV_INCLUDE_DIR})
foreach(module calib3d imgcodecs imgproc core)
  find_library(ACRO_OPENCV_${module}_LIBRARY opencv_${module} REQUIRED)
  target_link_libraries(acro::opencv INTERFACE ${ACRO_OPENCV_${module}_LIBRARY})
endforeach()
find_library(ACRO_OPENCV_aruco_LIBRARY opencv_aruco)
find_path(ACRO_OPENCV_ARUCO_INCLUDE_DIR opencv2/aruco/charuco.hpp PATH_SUFFIXES opencv4)
set(ACRO_HAVE_ARUCO OFF)
if(ACRO_OPENCV_aruco_LIBRARY AND ACRO_OPENCV_ARUCO_INCLUDE_DIR)
  set(ACRO_HAVE_ARUCO ON)
  target_link_libraries(acro::opencv INTERFACE ${ACRO_OPENCV_aruco_LIBRARY})
  target_compile_definitions(acro::opencv INTERFACE ACRO_HAVE_ARUCO=1)
endif()
message(STATUS "OpenCV modules in ${ACRO_OPENCV_INCLUDE_DIR}; ChArUco (aruco): ${ACRO_HAVE_ARUCO}")
# OpenCV's DNN module runs the pose networks (analysis/pose only; libopencv-dnn-dev).
find_library(ACRO_OPENCV_dnn_LIBRARY opencv_dnn REQUIRED)
add_library(acro::opencv_dnn INTERFACE IMPORTED)
target_link_libraries(acro::opencv_dnn INTERFACE ${ACRO_OPENCV_dnn_LIBRARY} acro::opencv)

# The pose models' conversion (tools/, run once by scripts/install-models.sh): the TFLite files are
# flatbuffers, read with flatbuffers' verifier (libflatbuffers-dev, header-only use), and written as
# ONNX with ONNX's own protobuf classes (libonnx-dev, libprotobuf-dev).
find_path(ACRO_FLATBUFFERS_INCLUDE_DIR flatbuffers/flatbuffers.h REQUIRED)
add_library(acro::flatbuffers INTERFACE IMPORTED)
target_include_directories(acro::flatbuffers INTERFACE ${ACRO_FLATBUFFERS_INCLUDE_DIR})
find_package(Protobuf REQUIRED)
find_package(ONNX REQUIRED)

# Cairo: every chart of every report, PNG and SVG, with no display (ui/report only).
pkg_check_modules(CAIRO REQUIRED IMPORTED_TARGET cairo cairo-svg cairo-png)

# SQLite and Nettle (SHA-256): the season library (analysis/library/src only; SQLite also in its
# tests, which write old and damaged library files).
pkg_check_modules(SQLITE3 REQUIRED IMPORTED_TARGET GLOBAL sqlite3)
pkg_check_modules(NETTLE REQUIRED IMPORTED_TARGET GLOBAL nettle)

# FFmpeg: video input and output, live sources (libavdevice: V4L2 cameras) (capture/src only).
pkg_check_modules(FFMPEG REQUIRED IMPORTED_TARGET libavformat libavcodec libswscale libavutil
                  libavdevice)

# Ceres and OpenMesh (analysis/*/src only).
find_package(Ceres 2.1 REQUIRED)
find_package(OpenMesh QUIET CONFIG)
if(NOT TARGET OpenMeshCore)
  # Debian's libopenmesh-dev ships headers and libraries without a usable CMake config in some versions.
  find_path(OPENMESH_INCLUDE_DIR OpenMesh/Core/Mesh/PolyMeshT.hh REQUIRED)
  find_library(OPENMESH_CORE_LIBRARY NAMES OpenMeshCore REQUIRED)
  add_library(OpenMeshCore UNKNOWN IMPORTED)
  set_target_properties(OpenMeshCore PROPERTIES IMPORTED_LOCATION "${OPENMESH_CORE_LIBRARY}"
                                                INTERFACE_INCLUDE_DIRECTORIES "${OPENMESH_INCLUDE_DIR}")
endif()

# VTK and Qt (ui/views and ui/studio, the 3D views and the window; nothing else needs them). Debian's VTK 9.1 config refers to MPI::MPI_C and JsonCpp::JsonCpp without
# creating them; without both targets CMake reports an error and does not regenerate correctly
# (../shared/SETUP-NOTES.md). Provide them before find_package(VTK).
if(ACRO_BUILD_UI)
  find_package(MPI COMPONENTS C)
  if(NOT TARGET JsonCpp::JsonCpp)
    pkg_check_modules(JSONCPP QUIET IMPORTED_TARGET jsoncpp)
    add_library(JsonCpp::JsonCpp INTERFACE IMPORTED)
    if(TARGET PkgConfig::JSONCPP)
      target_link_libraries(JsonCpp::JsonCpp INTERFACE PkgConfig::JSONCPP)
    endif()
  endif()
  find_package(X11 REQUIRED)  # ui/views asks the X server whether it answers (display.h)
  set(ACRO_VTK_COMPONENTS CommonCore CommonDataModel FiltersSources RenderingCore RenderingOpenGL2
    RenderingFreeType InteractionStyle)
  # The window (ui/studio) alone needs Qt and VTK's Qt module: the main install (the README's first
  # command, which draws the overlay) goes without them (scripts/demo.sh: ACRO_BUILD_STUDIO=OFF).
  if(ACRO_BUILD_STUDIO)
    find_package(Qt5 REQUIRED COMPONENTS Widgets)
    list(APPEND ACRO_VTK_COMPONENTS GUISupportQt)
  endif()
  find_package(VTK 9 REQUIRED COMPONENTS ${ACRO_VTK_COMPONENTS})
endif()

# Tests and benchmarks.
if(ACRO_BUILD_TESTS)
  find_package(GTest REQUIRED)
  # Simbody is a test oracle only (tests/dynamics); it is optional so that a build without it still
  # runs every other test, and the oracle test reports itself as skipped.
  find_package(Simbody QUIET)
endif()
if(ACRO_BUILD_BENCHMARKS)
  find_package(benchmark REQUIRED)
endif()
