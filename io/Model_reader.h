// Reading CAD and mesh files into bodies: the one entry point every command uses.
//
// Formats (chosen by content first, then by extension):
//   STEP (AP203, AP214, AP242), IGES and OpenCASCADE .brep through OpenCASCADE's data exchange;
//   OBJ with free-form geometry (cstype bspline / rat bspline / bezier, surf, curv, curv2, trim,
//   hole) through our own reader; triangle meshes (STL, polygon OBJ, PLY, OFF, glTF/GLB and the
//   rest assimp reads) through assimp. docs/import.md lists the entities and what happens to
//   the rest.
// No OpenCASCADE or assimp type appears here: readers live in io/internal/*.cpp.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "kernel/Body.h"

namespace extremal::io {

enum class Model_format { Automatic, Step, Iges, Brep, Obj_freeform, Mesh };

// Length units we know, with their size in millimetres.
// Returns 0 for an unknown name. Accepts "mm", "cm", "m", "um", "in", "ft", "km", "nm", ...
double unit_in_millimetres(const std::string& unit);

// Bounds on what reading one STEP, IGES or BREP file may take. Checked in two places: a scan
// of the file's text before OpenCASCADE sees it (the control-point counts, which are what a
// small hostile file uses to make a reader allocate without bound), and the child process that
// runs OpenCASCADE's reader (memory and time; docs/import.md, "Limits and containment").
// A file beyond a limit is refused with an Invalid_input naming the file, the entity and the
// limit. 0 turns a limit off.
struct Import_limits {
  // Control points of one B-spline surface (all rows) or curve.
  std::size_t max_patch_poles = 250'000;
  // Control points of all B-spline surfaces and curves of the file together.
  std::size_t max_total_poles = 10'000'000;
  // Resident memory of the reading process, in MiB (MiB = 2^20 bytes).
  std::size_t max_memory_mb = 4096;
  // Wall-clock time of the OpenCASCADE reading, in seconds.
  double max_seconds = 600.0;
  // Read STEP, IGES and BREP in a child process (the memory and time limits need it, and a
  // crash inside OpenCASCADE becomes an Invalid_input instead of ending the caller). Off: in
  // this process, with only the scan's limits.
  bool isolate = true;
};

// The limits a default-constructed Read_options starts from: Import_limits{} until a program
// (the CLI's --max-patch-poles and friends) sets others, before it reads any file.
Import_limits default_import_limits();
void set_default_import_limits(const Import_limits& limits);

struct Read_options {
  // Lengths in the result are in this unit; files are converted from their declared unit.
  std::string scene_unit = "mm";
  // Unit assumed for files that declare none (OBJ, STL, PLY, .brep, ...).
  std::string unitless_file_unit = "mm";
  Model_format format = Model_format::Automatic;
  // Non-exact conversions (offset surfaces, ...) are approximated to this tolerance, relative to
  // the model size; the achieved error is recorded in Face::approximation_error.
  double approximation_tolerance = 1e-7;
  // Trim_region boundary band, relative to each face's parameter extent (see Trim_region).
  double trim_tolerance = 1e-5;
  // Also build Face::trims for bare surfaces that have none (their natural domain boundary).
  bool keep_untrimmed = true;
  Import_limits limits = default_import_limits();
};

// An entity of the file that is not in the model (or is only partly), and why.
struct Skipped_entity {
  std::string entity;  // e.g. "STEP #123 ADVANCED_FACE", "face 7 of body 'bracket'", "line 12"
  std::string reason;
  std::string action;  // what the reader did instead ("skipped", "approximated", ...)
};

struct Model {
  std::string file;
  Model_format format = Model_format::Automatic;
  std::string format_name;         // "STEP AP214", "IGES", "OBJ free-form", "STL (assimp)", ...
  std::string file_unit;           // as declared or assumed
  std::string unit;                // the scene unit the bodies are in
  double scale_to_unit = 1.0;      // file lengths times this = scene lengths
  std::vector<Body> bodies;
  std::vector<Skipped_entity> skipped;
  std::vector<std::string> warnings;  // everything worth telling that is not a skipped entity
};

// Reads `path`. Throws Invalid_input naming the file and the reason when the file cannot be read
// at all (missing, empty, unknown format, not parseable, no usable entity); a readable file with
// bad entities gives the model plus Model::skipped.
Model read_model(const std::string& path, const Read_options& options = {});

// The same from bytes in memory, `name` used in messages and for the extension (fuzzing, tests).
Model read_model_from_memory(const std::string& name, const std::string& bytes,
                             const Read_options& options = {});

// The bodies of a file, for a scene entry (fits io/Scene.h's File_loader): `file_units` is the
// unit assumed when the file declares none, lengths come in `scene_units`. Each body keeps its
// placement in the file (Body::placement), which the scene composes with the entry's pose.
// Throws like read_model; skipped entities are not returned (use read_model to see them).
std::vector<Body> load_bodies(const std::string& path, const std::string& file_units,
                              const std::string& scene_units);

// The format `read_model` would pick for these leading bytes and file name.
Model_format detect_format(const std::string& name, const std::string& head);
std::string format_name(Model_format f);

}  // namespace extremal::io
