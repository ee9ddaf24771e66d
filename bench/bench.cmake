# Benchmark programs (generators for scaling runs); included by the top-level CMakeLists.txt.
