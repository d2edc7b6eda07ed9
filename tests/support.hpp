#pragma once
// Helpers shared by the test suites (no meshd types: the HTTP tests link none).

#include <fstream>
#include <sstream>
#include <string>

namespace meshd::test {

inline std::string read_file(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    std::ostringstream ss;
    ss << f.rdbuf();
    return ss.str();
}

}  // namespace meshd::test
