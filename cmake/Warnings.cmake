# refraster_options: the compile contract shared by every target of the project.
add_library(refraster_options INTERFACE)
target_compile_options(refraster_options INTERFACE
  -ffp-contract=off
  -Wall -Wextra -Wpedantic -Wconversion -Wsign-conversion -Wshadow -Wold-style-cast
  -Wdouble-promotion -Wimplicit-fallthrough -Wnon-virtual-dtor)
if(REFRASTER_WERROR)
  target_compile_options(refraster_options INTERFACE -Werror)
endif()
if(REFRASTER_SANITIZE)
  target_compile_options(refraster_options INTERFACE
    -fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer)
  target_link_options(refraster_options INTERFACE -fsanitize=address,undefined)
endif()
if(REFRASTER_FUZZ)
  # Every library gets coverage instrumentation and the sanitizers; only the fuzz executables
  # link libFuzzer's main (fuzz/CMakeLists.txt adds -fsanitize=fuzzer there).
  target_compile_options(refraster_options INTERFACE
    -fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=all
    -fno-omit-frame-pointer)
  target_link_options(refraster_options INTERFACE -fsanitize=address,undefined)
endif()
