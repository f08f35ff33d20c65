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

function(ecpair_target_defaults target)
  target_compile_features(${target} PUBLIC cxx_std_20)
  target_compile_options(${target} PRIVATE ${ECPAIR_WARNINGS})
  ecpair_target_instrumentation(${target})
endfunction()
