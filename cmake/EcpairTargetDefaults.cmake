# Compiler settings shared by every ecpair target: C++20, warnings as errors
# for project code, optional sanitizers (-DECPAIR_SANITIZE=address,undefined).

set(ECPAIR_WARNINGS
  -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wsign-conversion
  -Wnon-virtual-dtor -Wold-style-cast -Wcast-align -Woverloaded-virtual
  -Wimplicit-fallthrough -Werror)
# -Wnull-dereference is left out: with -O2, GCC 12 reports it inside Boost
# and libstdc++ headers (boost::program_options string values).

if(ECPAIR_SANITIZE)
  string(REPLACE "," ";" _ecpair_sanitizers "${ECPAIR_SANITIZE}")
  set(ECPAIR_SANITIZE_FLAGS "")
  foreach(_s IN LISTS _ecpair_sanitizers)
    list(APPEND ECPAIR_SANITIZE_FLAGS "-fsanitize=${_s}")
  endforeach()
  list(APPEND ECPAIR_SANITIZE_FLAGS -fno-omit-frame-pointer -fno-sanitize-recover=all)
endif()

function(ecpair_target_defaults target)
  target_compile_features(${target} PUBLIC cxx_std_20)
  target_compile_options(${target} PRIVATE ${ECPAIR_WARNINGS})
  if(ECPAIR_SANITIZE_FLAGS)
    target_compile_options(${target} PRIVATE ${ECPAIR_SANITIZE_FLAGS})
    target_link_options(${target} PUBLIC ${ECPAIR_SANITIZE_FLAGS})
  endif()
endfunction()
