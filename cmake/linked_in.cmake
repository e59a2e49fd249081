# How the libraries are linked: into the programs, so that a program loads
# nothing at start-up but the C library (`rocking --version` is most of what a
# short run costs otherwise: resolving symbols across a dozen shared objects).
#  - GSL and SUNDIALS from their static archives into programs (rocking::gsl,
#    rocking::sundials); the Python module, a shared object, takes their
#    shared libraries (Debian's archives are not all position-independent);
#  - {fmt}, spdlog and toml++ compiled in from their headers: the targets
#    fmt::fmt-header-only, spdlog::spdlog_header_only and rocking::toml;
#  - the `rocking` program carries libstdc++ and libgcc (apps/CMakeLists.txt).
# cpp-httplib and OpenMPI stay shared: they live in the plugins the program
# opens only for `rocking serve` and under mpirun.
find_library(ROCKING_GSL_ARCHIVE NAMES libgsl.a REQUIRED)
find_library(ROCKING_GSLCBLAS_ARCHIVE NAMES libgslcblas.a REQUIRED)
set(ROCKING_IN_PROGRAM "$<STREQUAL:$<TARGET_PROPERTY:TYPE>,EXECUTABLE>")
add_library(rocking_gsl INTERFACE)
target_link_libraries(rocking_gsl INTERFACE "$<${ROCKING_IN_PROGRAM}:${ROCKING_GSL_ARCHIVE}>"
                      "$<${ROCKING_IN_PROGRAM}:${ROCKING_GSLCBLAS_ARCHIVE}>" "$<$<NOT:${ROCKING_IN_PROGRAM}>:GSL::gsl>")
target_include_directories(rocking_gsl SYSTEM INTERFACE ${GSL_INCLUDE_DIRS})
add_library(rocking::gsl ALIAS rocking_gsl)
find_package(SUNDIALS 6 REQUIRED COMPONENTS cvode arkode)
add_library(rocking_sundials_libraries INTERFACE)
target_link_libraries(rocking_sundials_libraries INTERFACE
                      "$<${ROCKING_IN_PROGRAM}:SUNDIALS::cvode_static>" "$<${ROCKING_IN_PROGRAM}:SUNDIALS::arkode_static>"
                      "$<$<NOT:${ROCKING_IN_PROGRAM}>:SUNDIALS::cvode>" "$<$<NOT:${ROCKING_IN_PROGRAM}>:SUNDIALS::arkode>")
add_library(rocking::sundials_libraries ALIAS rocking_sundials_libraries)

# spdlog's header-only target names the shared {fmt}; it takes {fmt}'s headers.
set_property(TARGET spdlog::spdlog_header_only PROPERTY INTERFACE_LINK_LIBRARIES Threads::Threads fmt::fmt-header-only)

# toml++ as headers (Debian's target asks for its shared library).
add_library(rocking_toml INTERFACE)
get_target_property(ROCKING_TOML_INCLUDES tomlplusplus::tomlplusplus INTERFACE_INCLUDE_DIRECTORIES)
target_include_directories(rocking_toml SYSTEM INTERFACE ${ROCKING_TOML_INCLUDES})
target_compile_definitions(rocking_toml INTERFACE TOML_HEADER_ONLY=1)
add_library(rocking::toml ALIAS rocking_toml)
