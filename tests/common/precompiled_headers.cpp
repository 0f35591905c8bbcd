// The source of coopdyn_test_pch, the target that builds the tests' precompiled headers
// (tests/CMakeLists.txt); it has nothing of its own to compile.
