# Options for `cmake --graphviz` (./dev graph): the library graph only, without tests, benchmarks and
# third-party libraries.
set(GRAPHVIZ_EXECUTABLES OFF)
set(GRAPHVIZ_EXTERNAL_LIBS OFF)
set(GRAPHVIZ_IGNORE_TARGETS "tiltfield_warnings;tiltfield_openmesh;test_.*;bench_.*")
set(GRAPHVIZ_GENERATE_PER_TARGET OFF)
set(GRAPHVIZ_GENERATE_DEPENDERS OFF)
