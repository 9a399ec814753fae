# Shared build settings, applied per target (never through global CMAKE_CXX_FLAGS).

add_library(geom_options INTERFACE)
target_compile_options(geom_options INTERFACE -Wall -Wextra -Wpedantic
                       $<$<BOOL:${GEOM_WERROR}>:-Werror>)
if(GEOM_SANITIZE)
  target_compile_options(geom_options INTERFACE -fsanitize=address,undefined
                         -fno-sanitize-recover=undefined -fno-omit-frame-pointer)
  target_link_options(geom_options INTERFACE -fsanitize=address,undefined)
endif()

# geom_add_library(<name> SOURCES ... [PUBLIC_DEPS ...] [PRIVATE_DEPS ...])
# Creates the static library geom_<name> (alias geom::<name>) for the capability folder
# geom/<name>; the include path is the repository root, so headers read <geom/<name>/x.h>.
function(geom_add_library name)
  cmake_parse_arguments(ARG "" "" "SOURCES;PUBLIC_DEPS;PRIVATE_DEPS" ${ARGN})
  add_library(geom_${name} STATIC ${ARG_SOURCES})
  add_library(geom::${name} ALIAS geom_${name})
  set_target_properties(geom_${name} PROPERTIES EXPORT_NAME ${name})
  target_include_directories(geom_${name} PUBLIC
    $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}> $<INSTALL_INTERFACE:include>)
  target_compile_features(geom_${name} PUBLIC cxx_std_20)
  target_link_libraries(geom_${name} PUBLIC ${ARG_PUBLIC_DEPS}
                        PRIVATE ${ARG_PRIVATE_DEPS} $<BUILD_INTERFACE:geom_options>)
  set_property(GLOBAL APPEND PROPERTY GEOM_LIBRARIES geom_${name})
  # Fuzzing build (clang): every library is instrumented for coverage and sanitizers; the
  # targets in tests/fuzz link with -fsanitize=fuzzer.
  if(GEOM_BUILD_FUZZERS)
    target_compile_options(geom_${name} PRIVATE -fsanitize=fuzzer-no-link,address,undefined
                           -fno-omit-frame-pointer -fno-sanitize-recover=all)
    target_link_options(geom_${name} INTERFACE -fsanitize=address,undefined)
  endif()
endfunction()
