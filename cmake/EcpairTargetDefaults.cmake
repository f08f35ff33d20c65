# Compiler settings shared by every ecpair target: C++20, the project's
# warnings (errors with -DECPAIR_WERROR=ON, as CI builds), optional
# sanitizers (-DECPAIR_SANITIZE=address,undefined) and, in a fuzz build
# (-DECPAIR_FUZZ=ON, clang), coverage instrumentation of everything a fuzz
# target links.

set(ECPAIR_WARNINGS
  -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wsign-conversion
  -Wnon-virtual-dtor -Wold-style-cast -Wcast-align -Woverloaded-virtual
  -Wimplicit-fallthrough)
# -Wnull-dereference is left out: with -O2, GCC 12 reports it inside Boost
# and libstdc++ headers (boost::program_options string values).
# GCC warns when a class holds a type of an anonymous namespace outside the
# main file, because a header could define it twice; in a unity build every
# source file is outside the main file, so the warning would only be noise.
if(CMAKE_UNITY_BUILD AND CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
  list(APPEND ECPAIR_WARNINGS -Wno-subobject-linkage)
endif()
if(ECPAIR_WERROR)
  list(APPEND ECPAIR_WARNINGS -Werror)
endif()

set(ECPAIR_SANITIZE_FLAGS "")
if(ECPAIR_SANITIZE)
  string(REPLACE "," ";" _ecpair_sanitizers "${ECPAIR_SANITIZE}")
  foreach(_s IN LISTS _ecpair_sanitizers)
    list(APPEND ECPAIR_SANITIZE_FLAGS "-fsanitize=${_s}")
  endforeach()
  list(APPEND ECPAIR_SANITIZE_FLAGS -fno-omit-frame-pointer -fno-sanitize-recover=all)
endif()

# The fuzz build instruments every library (and program) for libFuzzer's
# coverage and checks them with ASan and UBSan; only the fuzz binaries link
# libFuzzer itself (-fsanitize=fuzzer, see ecpair_add_fuzz_target).
set(ECPAIR_FUZZ_COMPILE_FLAGS "")
set(ECPAIR_FUZZ_LINK_FLAGS "")
if(ECPAIR_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
    message(FATAL_ERROR "ECPAIR_FUZZ needs clang (-DCMAKE_CXX_COMPILER=clang++), not ${CMAKE_CXX_COMPILER_ID}")
  endif()
  set(ECPAIR_FUZZ_COMPILE_FLAGS -fsanitize=fuzzer-no-link,address,undefined -fno-omit-frame-pointer
      -fno-sanitize-recover=all)
  set(ECPAIR_FUZZ_LINK_FLAGS -fsanitize=address,undefined)
endif()

# Sanitizer and fuzz instrumentation only: for code that is not held to the
# project's warnings (the generated protobuf sources).
function(ecpair_target_instrumentation target)
  if(ECPAIR_SANITIZE_FLAGS)
    target_compile_options(${target} PRIVATE ${ECPAIR_SANITIZE_FLAGS})
    target_link_options(${target} PUBLIC ${ECPAIR_SANITIZE_FLAGS})
  endif()
  if(ECPAIR_FUZZ_COMPILE_FLAGS)
    target_compile_options(${target} PRIVATE ${ECPAIR_FUZZ_COMPILE_FLAGS})
    target_link_options(${target} PUBLIC ${ECPAIR_FUZZ_LINK_FLAGS})
  endif()
endfunction()

# Precompiled headers: spdlog and fmt (through ecpair/common/log.hpp) are most
# of what a library file costs to compile, Catch2's single header most of a
# test file. A build compiles each once, in the target that holds it
# (ecpair_common for libraries and programs, ecpair_test_pch for the tests),
# and every other target reuses it. A reusing target must have the defines
# the header was built with, which it gets by linking ecpair_common; GCC
# refuses the header otherwise (-Winvalid-pch, an error with ECPAIR_WERROR).
option(ECPAIR_PCH "Build with precompiled headers" ON)

# ecpair_target_defaults(<target> [PCH_FROM <holder> | NO_PCH]): the flags
# above, and the precompiled header of <holder> (default ecpair_common);
# NO_PCH for a target that does not link ecpair_common.
function(ecpair_target_defaults target)
  cmake_parse_arguments(D "NO_PCH" "PCH_FROM" "" ${ARGN})
  target_compile_features(${target} PUBLIC cxx_std_20)
  target_compile_options(${target} PRIVATE ${ECPAIR_WARNINGS})
  ecpair_target_instrumentation(${target})
  if(NOT D_PCH_FROM)
    set(D_PCH_FROM ecpair_common)
  endif()
  if(ECPAIR_PCH AND NOT D_NO_PCH AND NOT target STREQUAL D_PCH_FROM)
    target_precompile_headers(${target} REUSE_FROM ${D_PCH_FROM})
  endif()
endfunction()
