# acro_add_library(NAME <layer> [SRCS ...] [PUBLIC_DEPS ...] [PRIVATE_DEPS ...])
#   Makes target acro_<layer> from <layer>/src/*, exporting <layer>/include PUBLIC. A layer with no
#   sources yet becomes an INTERFACE target so that dependants can already link it.
# acro_add_test(NAME <layer>/<unit> SRCS ... [DEPS ...] [NO_NDEBUG])
#   A GoogleTest executable registered with ctest under the name <layer>/<unit>.

set(ACRO_WARNINGS -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor -Wcast-align -Wno-psabi)
# GCC 12 reports -Wrestrict inside libstdc++ for std::string::operator=(const char*) at -O2 and above
# (GCC bugs 105329 and 105651, fixed in GCC 13): a false positive in the library, not in our code.
if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU" AND CMAKE_CXX_COMPILER_VERSION VERSION_LESS 13)
  list(APPEND ACRO_WARNINGS -Wno-restrict)
endif()

function(acro_set_warnings target)
  target_compile_options(${target} PRIVATE ${ACRO_WARNINGS})
  if(ACRO_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()

function(acro_add_library)
  cmake_parse_arguments(ARG "" "NAME" "SRCS;PUBLIC_DEPS;PRIVATE_DEPS" ${ARGN})
  set(target acro_${ARG_NAME})
  if(ARG_SRCS)
    add_library(${target} STATIC ${ARG_SRCS})
    target_include_directories(${target} PUBLIC ${CMAKE_CURRENT_SOURCE_DIR}/include)
    target_link_libraries(${target} PUBLIC ${ARG_PUBLIC_DEPS} PRIVATE ${ARG_PRIVATE_DEPS})
    target_compile_features(${target} PUBLIC cxx_std_20)
    set_target_properties(${target} PROPERTIES POSITION_INDEPENDENT_CODE ON)
    acro_set_warnings(${target})
  else()
    add_library(${target} INTERFACE)
    target_include_directories(${target} INTERFACE ${CMAKE_CURRENT_SOURCE_DIR}/include)
    target_link_libraries(${target} INTERFACE ${ARG_PUBLIC_DEPS})
    target_compile_features(${target} INTERFACE cxx_std_20)
  endif()
  add_library(acro::${ARG_NAME} ALIAS ${target})
endfunction()

function(acro_add_test)
  cmake_parse_arguments(ARG "NO_NDEBUG" "NAME" "SRCS;DEPS" ${ARGN})
  string(REPLACE "/" "_" target "test_${ARG_NAME}")
  add_executable(${target} ${ARG_SRCS})
  target_link_libraries(${target} PRIVATE ${ARG_DEPS} GTest::gtest GTest::gtest_main acro_test_support)
  target_compile_features(${target} PRIVATE cxx_std_20)
  acro_set_warnings(${target})
  if(ARG_NO_NDEBUG)
    # Simbody 3.7's headers change class layouts under NDEBUG (../shared/SETUP-NOTES.md).
    target_compile_options(${target} PRIVATE -UNDEBUG)
  endif()
  add_test(NAME ${ARG_NAME} COMMAND ${target})
  set_tests_properties(${ARG_NAME} PROPERTIES
    ENVIRONMENT "ACRO_SOURCE_DIR=${PROJECT_SOURCE_DIR};ACRO_BINARY_DIR=${PROJECT_BINARY_DIR}")
endfunction()

function(acro_add_benchmark)
  cmake_parse_arguments(ARG "" "NAME" "SRCS;DEPS" ${ARGN})
  add_executable(${ARG_NAME} ${ARG_SRCS})
  target_link_libraries(${ARG_NAME} PRIVATE ${ARG_DEPS} benchmark::benchmark)
  target_compile_features(${ARG_NAME} PRIVATE cxx_std_20)
  acro_set_warnings(${ARG_NAME})
  set_target_properties(${ARG_NAME} PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${PROJECT_BINARY_DIR}/bench)
endfunction()
