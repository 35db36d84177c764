#pragma once
// Test fixtures made by Gmsh itself: a script of the test's own (Save commands included) run by
// Gmsh's library in this process, in `folder`. needlesim's reader refuses such scripts (it never
// writes); tests that need .msh or .stl files Gmsh wrote make them here.
#include <gmsh.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace needlesim::test_support {

inline void gmshWrites(const std::filesystem::path& folder, const std::string& name, const std::string& script) {
  std::filesystem::create_directories(folder);
  std::ofstream(folder / name) << script;
  const auto before = std::filesystem::current_path();
  std::filesystem::current_path(folder);
  gmsh::initialize(0, nullptr, false);
  gmsh::option::setNumber("General.Terminal", 0);
  gmsh::open((folder / name).string());
  gmsh::finalize();
  std::filesystem::current_path(before);
}

}  // namespace needlesim::test_support
