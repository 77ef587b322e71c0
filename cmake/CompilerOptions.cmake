# Warnings, optimisation and sanitizer flags shared by every pbf target.
add_library(pbf_options INTERFACE)
target_compile_options(pbf_options INTERFACE -Wall -Wextra -Wpedantic -Wshadow -Wconversion
                                             -Wno-sign-conversion -Wnon-virtual-dtor)
if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
  # GCC 12 reports false positives inside libstdc++'s std::string at -O3
  # (GCC bugs 105329 and 105651).
  target_compile_options(pbf_options INTERFACE -Wno-restrict -Wno-stringop-overflow)
endif()
if(PBF_WERROR)
  target_compile_options(pbf_options INTERFACE -Werror)
endif()
# sqrt without errno: otherwise every std::sqrt in a neighbour loop carries a
# branch to a libm call for negative inputs, which forces the loop's
# accumulators out of registers and blocks vectorisation (measured: the
# density and correction loops ran ~2x slower). pbf never reads errno.
target_compile_options(pbf_options INTERFACE -fno-math-errno)
if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
  # Masked (not scalar) epilogues: a particle has ~30 neighbours, so with
  # 16-lane AVX-512 vectors half of every neighbour loop is the epilogue.
  target_compile_options(pbf_options INTERFACE --param=vect-partial-vector-usage=2)
endif()
if(PBF_NATIVE)
  target_compile_options(pbf_options INTERFACE -march=native)
  # The SIMD loops (Highway) are compiled for the host's instruction set only
  # and called directly. Portable builds compile them for every x86 target and
  # choose at run time.
  target_compile_definitions(pbf_options INTERFACE HWY_COMPILE_ONLY_STATIC=1)
endif()
if(PBF_SANITIZE)
  target_compile_options(pbf_options INTERFACE -fsanitize=${PBF_SANITIZE} -fno-omit-frame-pointer
                                               -fno-sanitize-recover=all)
  target_link_options(pbf_options INTERFACE -fsanitize=${PBF_SANITIZE})
endif()
