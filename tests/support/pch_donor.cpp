// Empty on purpose: the target tests_pch exists to compile the test programs' shared precompiled header
// (tests/CMakeLists.txt), and a target needs a source.
