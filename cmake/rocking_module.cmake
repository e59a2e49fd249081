# rocking_module(NAME name DEPS dep... LIBS lib...)
# One library per module folder: target rocking_<name>, alias rocking::<name>,
# interface unit <name>.cppm exporting `rocking.<name>` (any other *.cppm
# beside it is one of its partitions), implementation units *.cpp beside it.
# The project's Eigen header (modules/support) is visible to all.
function(rocking_module)
  cmake_parse_arguments(ARG "" "NAME" "DEPS;LIBS" ${ARGN})
  set(target rocking_${ARG_NAME})
  file(GLOB impl CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/*.cpp)
  file(GLOB partitions CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/*.cppm)
  list(REMOVE_ITEM partitions ${CMAKE_CURRENT_SOURCE_DIR}/${ARG_NAME}.cppm)
  add_library(${target})
  add_library(rocking::${ARG_NAME} ALIAS ${target})
  target_sources(${target}
    PUBLIC FILE_SET CXX_MODULES FILES ${CMAKE_CURRENT_SOURCE_DIR}/${ARG_NAME}.cppm ${partitions}
    PRIVATE ${impl})
  target_include_directories(${target} PUBLIC ${PROJECT_SOURCE_DIR}/modules/support)
  target_link_libraries(${target} PUBLIC Eigen3::Eigen ${ARG_DEPS} ${ARG_LIBS})
endfunction()
