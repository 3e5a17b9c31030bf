# slamprep_library(NAME): a static library from every .cpp below the calling folder, or an
# interface library while the folder has none yet. The folder layout is the architecture.
function(slamprep_library name)
  file(GLOB_RECURSE sources CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/*.cpp)
  if(sources)
    add_library(${name} STATIC ${sources})
    set(scope PUBLIC)
  else()
    add_library(${name} INTERFACE)
    set(scope INTERFACE)
  endif()
  target_include_directories(${name} ${scope} ${SLAMPREP_ROOT})
  set(SLAMPREP_SCOPE ${scope} PARENT_SCOPE)
endfunction()
