// Shared by the rigid-body examples: the output directory from `--output DIR` (default ".").
#pragma once
#include <cstring>
#include <filesystem>
#include <string>

inline std::filesystem::path output_dir(int argc, char** argv) {
    std::filesystem::path dir = ".";
    for (int i = 1; i + 1 < argc; ++i)
        if (std::strcmp(argv[i], "--output") == 0) dir = argv[i + 1];
    std::filesystem::create_directories(dir);
    return dir;
}
