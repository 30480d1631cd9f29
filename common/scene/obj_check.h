// The grammar of a Wavefront OBJ file, checked before assimp reads it.
//
// assimp 5.2's OBJ parser dispatches on a line's first character and reads
// numbers with its own scanner, so a malformed file is not refused but read
// wrongly, and a fuzzed one corrupted the heap (fuzz_mesh, 2026-12-02: a
// face line with NUL bytes and mixed "v/t/n" and "v/t" forms). Measured on
// Debian's libassimp 5.2.5, each of these loads without an error and gives
// another mesh than the file says:
//   v .5 0 0         the vertex is dropped (a number must start with a
//   v 0 0 0 1 2      digit or sign; 5 numbers are none of 3, 4, 6), so every
//                    later face index points one vertex further
//   f 01 2 3         "01" is read as the indices 1 and 1 (also "+1")
//   foo 1 2 3        read as a face (any word starting with 'f')
//     f 1 2 3        skipped (a statement after leading blanks)
//   v 1 0 0 \        the continuation swallows the next line
// CheckObjStructure refuses all of these with the line and the reason, so
// what passes is read by assimp as written.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

namespace ausbau {

// Throws InputError ("<name>: malformed OBJ file (line N: <problem>)") on:
// a control character (NUL, ...) other than tab and line ends; a statement
// after leading blanks; a line continuation; a word starting like a geometry
// statement that is none (v vt vn vp f l p g o); a vertex of other than 3, 4
// or 6 numbers, a normal of other than 3, a texture coordinate of other than
// 2 or 3; a number assimp would misread; a face, line or point reference
// that is not "v", "v/t", "v//n" or "v/t/n" with nonzero integers without
// sign '+' or leading zeros, the same form for every corner; or an index
// (negative: relative) outside the vertices, texture coordinates or normals
// the file has. Materials, groups, objects, smoothing groups, comments and
// free-form sections ("cstype" ... "end") are not checked further.
void CheckObjStructure(const std::filesystem::path& path, const std::string& name);

// The first control character of a line of a text mesh format (OBJ, ASCII
// PLY, OFF), as "0x0C"; empty when there is none. Tab is allowed, and '\r'
// at the end (CRLF files). Our checks split words at every blank that
// std::isspace knows, assimp's parsers only at ' ' and '\t': a form feed or
// NUL would make the two read different words (a PLY header with
// "\fend_header" passed our check, and assimp never found its end).
std::string FirstControlCharacter(std::string_view line);

}  // namespace ausbau
