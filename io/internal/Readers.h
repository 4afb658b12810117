// The format-specific readers behind read_model. Not API: every function fills `model` (bodies
// in the scene unit, skipped entities, warnings) or throws Invalid_input naming the file.
#pragma once

#include <map>
#include <string>

#include "io/Model_reader.h"

namespace extremal::io::internal {

// What the scan of a STEP or IGES file's text found wrong with single entities (a B-spline's
// knots, multiplicities, weights, degree), by the label OpenCASCADE's model gives the entity
// ("#20" in STEP, "D45" in IGES): the reason given when OpenCASCADE then fails on it.
struct Cad_scan {
  std::map<std::string, std::string> entity_problems;
};

// The scan of the text before OpenCASCADE reads it (Cad_scan.cpp). Throws Invalid_input naming
// `name`, the entity and the rule for a file that is truncated (an entity, string or section cut
// off, no END-ISO-10303-21 / no Terminate record), has a reference cycle (an entity that refers
// to itself, directly or through others) or a name defined twice, or a B-spline whose control
// points exceed `limits` (per B-spline, or in all) or whose announced counts exceed what it holds
// (IGES). Time and memory linear in the file.
void scan_step(const std::string& name, const std::string& bytes, const Import_limits& limits,
               Cad_scan& out);
void scan_iges(const std::string& name, const std::string& bytes, const Import_limits& limits,
               Cad_scan& out);

// STEP, IGES and .brep through OpenCASCADE (Occt_reader.cpp), in this process. `path` is a
// file on disk; `scan` names the reasons of entities OpenCASCADE fails on.
void read_occt(const std::string& path, Model_format format, const Read_options& options,
               const Cad_scan& scan, Model& model);

// read_occt in a child process (Isolated_reader.cpp) under options.limits' memory and time
// limits: the model comes back through a pipe; a crash, a limit reached or an exception in the
// child is an Invalid_input naming `name` (the file as the user gave it).
void read_occt_isolated(const std::string& path, const std::string& name, Model_format format,
                        const Read_options& options, const Cad_scan& scan, Model& model);

// The model as bytes and back (Isolated_reader.cpp): exact (doubles bit for bit), for the pipe.
std::string encode_model(const Model& model);
Model decode_model(const std::string& bytes);

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
