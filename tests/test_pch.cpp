// Nothing to compile: this file gives the target that builds the tests'
// precompiled header (ecpair_test_pch, tests/CMakeLists.txt) a source.
