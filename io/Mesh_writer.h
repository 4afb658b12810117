// Writing triangle meshes: binary STL, ASCII PLY and OBJ, chosen by the file's extension.
//
// STL stores single-precision coordinates and a facet normal computed from each triangle (its
// vertices repeated per facet); PLY and OBJ store the indexed mesh with coordinates written in
// the shortest form that reads back to the same double. Every file reads back through
// io::read_model as one mesh body.
#pragma once

#include <string>

#include "kernel/Body.h"

namespace extremal::io {

enum class Mesh_file_format { Stl, Ply, Obj };

// The format for the extension of `path` (.stl, .ply, .obj, any case). Throws Invalid_input
// naming the file when it has another extension or none.
Mesh_file_format mesh_file_format(const std::string& path);

// Throws Invalid_input naming the file and the reason when `path` cannot be written: its folder
// is missing or not writable, or it is a folder or a read-only file. Creates nothing (a check
// before long work; write_mesh still reports what fails when writing).
void check_writable(const std::string& path);

// Writes `mesh` to `path` in the format of its extension; `comment` goes into the header (STL:
// its first 80 bytes, never starting with "solid"). Throws Invalid_input naming the file and
// the reason (bad extension, cannot open, write failed) and Precondition_violation for a
// triangle whose vertex index is out of range.
void write_mesh(const std::string& path, const Triangle_mesh& mesh,
                const std::string& comment = "written by extremal");

}  // namespace extremal::io
