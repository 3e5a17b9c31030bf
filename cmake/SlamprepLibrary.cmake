# slamprep_library(NAME [RECURSE] [PUBLIC deps...] [PRIVATE deps...] [INTERNAL headers...])
# A static library `slamprep_NAME` (alias and exported name `slamprep::NAME`) from the .cpp files of
# the calling folder (and its subfolders with RECURSE). Its headers install under
# include/slamprep/<folder>/, so `#include "slamprep/core/se2.hpp"` reads the same in the tree and
# installed; except the INTERNAL ones (paths relative to the folder): headers only the library's
# own sources include, which are not part of its interface.
function(slamprep_library name)
  cmake_parse_arguments(ARG "RECURSE" "" "PUBLIC;PRIVATE;INTERNAL" ${ARGN})
  if(ARG_RECURSE)
    file(GLOB_RECURSE sources CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/*.cpp)
    file(GLOB_RECURSE headers CONFIGURE_DEPENDS RELATIVE ${SLAMPREP_ROOT}
         ${CMAKE_CURRENT_SOURCE_DIR}/*.hpp)
  else()
    file(GLOB sources CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/*.cpp)
    file(GLOB headers CONFIGURE_DEPENDS RELATIVE ${SLAMPREP_ROOT} ${CMAKE_CURRENT_SOURCE_DIR}/*.hpp)
  endif()
  set(target slamprep_${name})
  add_library(${target} STATIC ${sources})
  add_library(slamprep::${name} ALIAS ${target})
  set_target_properties(${target} PROPERTIES EXPORT_NAME ${name} POSITION_INDEPENDENT_CODE ON)
  slamprep_unity_build(${target})
  target_compile_features(${target} PUBLIC cxx_std_20)
  target_compile_options(${target} PRIVATE ${SLAMPREP_WARNINGS})
  target_include_directories(${target} PUBLIC $<BUILD_INTERFACE:${SLAMPREP_INCLUDE_ROOT}>
                                              $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  target_link_libraries(${target} PUBLIC ${ARG_PUBLIC} PRIVATE ${ARG_PRIVATE})

  install(TARGETS ${target} EXPORT slamprepTargets ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
  file(RELATIVE_PATH folder ${SLAMPREP_ROOT} ${CMAKE_CURRENT_SOURCE_DIR})
  list(TRANSFORM ARG_INTERNAL PREPEND ${folder}/)
  foreach(internal ${ARG_INTERNAL})
    if(NOT internal IN_LIST headers)
      message(FATAL_ERROR "slamprep_library(${name}): INTERNAL ${internal} is not a header of it")
    endif()
  endforeach()
  list(REMOVE_ITEM headers ${ARG_INTERNAL})
  foreach(header ${headers})
    get_filename_component(dir ${header} DIRECTORY)
    install(FILES ${SLAMPREP_ROOT}/${header} DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/slamprep/${dir})
  endforeach()
endfunction()

# slamprep_unity_build(TARGET): batches TARGET's sources when SLAMPREP_UNITY_BUILD is on. A file
# whose file-local names (anonymous namespace) clash with another file's of the same target is
# kept out of the batches with set_source_files_properties(... SKIP_UNITY_BUILD_INCLUSION ON)
# in its folder's CMakeLists.txt.
function(slamprep_unity_build target)
  set_target_properties(${target} PROPERTIES UNITY_BUILD ${SLAMPREP_UNITY_BUILD}
                                             UNITY_BUILD_BATCH_SIZE ${SLAMPREP_UNITY_BATCH_SIZE})
  # GCC takes an included .cpp for a header and warns when a class of it holds a file-local type
  # (-Wsubobject-linkage); in a unity batch that is every file, so the warning means nothing.
  if(SLAMPREP_UNITY_BUILD AND CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
    target_compile_options(${target} PRIVATE -Wno-subobject-linkage)
  endif()
endfunction()
