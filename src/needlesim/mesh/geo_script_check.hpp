#pragma once
// A lexical check of a Gmsh script (.geo) before Gmsh reads it: comments and string literals
// skipped, words read with their line numbers (Gmsh's own lexer rules), and every command that
// would act outside the geometry (run a program, write, print or save a file, end the reader,
// talk to a server) refused at file:line, as is an Include or Merge of anything but a plain
// string literal naming a file in the script's folder. Included and merged scripts are checked
// in turn. The sandbox of mesh/isolated_reader is the guarantee; this check names the line.
#include <string>

namespace needlesim::mesh {

// Throws InputError (file:line, the command, what a script may contain) for a refused command.
void checkGeoScript(const std::string& path);

// Whether Gmsh reads the file as a script: a .geo, or any file that is neither a mesh (its first
// bytes a .msh section) nor in a format Gmsh recognises by its extension.
bool gmshReadsAsScript(const std::string& path);

}  // namespace needlesim::mesh
