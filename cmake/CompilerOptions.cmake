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
if(PBF_NATIVE)
  target_compile_options(pbf_options INTERFACE -march=native)
endif()
if(PBF_SANITIZE)
  target_compile_options(pbf_options INTERFACE -fsanitize=${PBF_SANITIZE} -fno-omit-frame-pointer
                                               -fno-sanitize-recover=all)
  target_link_options(pbf_options INTERFACE -fsanitize=${PBF_SANITIZE})
endif()
