// Host of the tests' precompiled header (tests/CMakeLists.txt): an executable
// compiled like the tests, so that they can reuse it.
int main() { return 0; }
