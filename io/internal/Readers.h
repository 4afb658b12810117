// The format-specific readers behind read_model. Not API: every function fills `model` (bodies
// in the scene unit, skipped entities, warnings) or throws Invalid_input naming the file.
#pragma once

#include <string>

#include "io/Model_reader.h"

namespace extremal::io::internal {

// STEP, IGES and .brep through OpenCASCADE (Occt_reader.cpp). `path` is a file on disk.
void read_occt(const std::string& path, Model_format format, const Read_options& options,
               Model& model);

// OBJ with free-form geometry (Obj_freeform_reader.cpp). `name` for messages only.
void read_obj_freeform(const std::string& name, const std::string& text,
                       const Read_options& options, Model& model);

// Meshes through assimp (Mesh_reader.cpp): from the file when `bytes` is null (so that OBJ
// material and glTF buffer files next to it are found), else from memory.
void read_mesh(const std::string& path, const std::string* bytes, const Read_options& options,
               Model& model);

// Millimetres per unit for the scene and the assumed unit of unitless files; throws
// Invalid_input for unknown names.
double scene_scale(const std::string& file_unit, const Read_options& options);

// Gives every body a name unique in the model: the source name, "<source>#k" for repeats.
void make_names_unique(Model& model, const std::string& fallback);

}  // namespace extremal::io::internal
