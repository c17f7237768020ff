// Builds tests/precompiled.hpp once for every test program (tests/CMakeLists.txt, REUSE_FROM).
