// The source of coopdyn_test_pch and coopdyn_benchmark_pch, the targets that build the tests' and
// the benchmarks' precompiled headers (tests/CMakeLists.txt, benchmarks/CMakeLists.txt); it has
// nothing of its own to compile.
