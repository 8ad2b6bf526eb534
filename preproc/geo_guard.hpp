// A .geo is a program in gmsh's language, and gmsh runs it as it parses it: it can run shell
// commands (System, SystemCall), write files (Save, Print, Printf(...) > "file"), read other
// files (Merge, ShapeFromFile, ListFromFile), end the process (Exit, Abort) or pause it
// (Sleep). check_geo_program reads the .geo before gmsh does, with gmsh's own lexical rules
// (comments // and /* */, strings in "..." or '...' without escapes), and refuses any of those
// statements outside comments and strings, in the .geo and in every file it Includes. An
// Include must name a plain string, a file in the .geo's own folder or below it, and must not
// include itself again. gmsh also reads FILE.geo.opt after FILE.geo when it exists: it is
// checked the same way. The allowed subset is listed in docs/scenes.md.
#pragma once
#include <string>

namespace talus::preproc {

// Throws talus::Error "FILE:LINE: statement 'NAME' is not allowed in a Talus .geo (WHY)" for
// the first refused statement. A missing top-level file is left to the caller.
void check_geo_program(const std::string& geo_path);

}  // namespace talus::preproc
