// Triangle meshes through assimp: STL, polygon OBJ, PLY, OFF, glTF/GLB and the other formats
// assimp 5 reads. Polygons are triangulated; points and lines are reported and left out. Node
// transforms are applied, so the body's triangles are in the file frame; the whole file is one
// body.
#include <algorithm>
#include <numeric>
#include <cmath>
#include <sstream>

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include "io/internal/Readers.h"
#include "kernel/Error.h"

namespace extremal::io::internal {

namespace {

std::string lower_ext(const std::string& name) {
  const std::string base = name.substr(name.find_last_of("/\\") + 1);
  const auto dot = base.find_last_of('.');
  std::string e = dot == std::string::npos ? std::string() : base.substr(dot + 1);
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return std::tolower(c); });
  return e;
}

std::string stem(const std::string& name) {
  std::string s = name.substr(name.find_last_of("/\\") + 1);
  const auto dot = s.find_last_of('.');
  return dot == std::string::npos || dot == 0 ? s : s.substr(0, dot);
}

struct Collector {
  const aiScene* scene;
  Body* body;
  Model* model;
  double scale;
  std::size_t skipped_points = 0, skipped_lines = 0, bad_faces = 0, bad_vertices = 0;

  void node(const aiNode* n, const aiMatrix4x4& parent, int depth) {
    if (!n || depth > 256) return;
    const aiMatrix4x4 m = parent * n->mTransformation;
    for (unsigned k = 0; k < n->mNumMeshes; ++k) {
      if (n->mMeshes[k] >= scene->mNumMeshes) continue;
      mesh(scene->mMeshes[n->mMeshes[k]], m);
    }
    for (unsigned c = 0; c < n->mNumChildren; ++c) node(n->mChildren[c], m, depth + 1);
  }

  void mesh(const aiMesh* me, const aiMatrix4x4& m) {
    if (!me || !me->mVertices) return;
    Triangle_mesh& out = body->mesh;
    const int base = static_cast<int>(out.vertices.size());
    for (unsigned i = 0; i < me->mNumVertices; ++i) {
      aiVector3D v = m * me->mVertices[i];
      double x = v.x * scale, y = v.y * scale, z = v.z * scale;
      if (!(std::isfinite(x) && std::isfinite(y) && std::isfinite(z))) {
        ++bad_vertices;
        x = y = z = 0.0;
      }
      out.vertices.emplace_back(x, y, z);
    }
    for (unsigned f = 0; f < me->mNumFaces; ++f) {
      const aiFace& face = me->mFaces[f];
      if (face.mNumIndices == 1) {
        ++skipped_points;
        continue;
      }
      if (face.mNumIndices == 2) {
        ++skipped_lines;
        continue;
      }
      if (face.mNumIndices != 3 || !face.mIndices) {
        ++bad_faces;
        continue;
      }
      bool ok = true;
      for (int c = 0; c < 3; ++c) ok = ok && face.mIndices[c] < me->mNumVertices;
      if (!ok) {
        ++bad_faces;
        continue;
      }
      out.triangles.push_back({base + static_cast<int>(face.mIndices[0]),
                               base + static_cast<int>(face.mIndices[1]),
                               base + static_cast<int>(face.mIndices[2])});
    }
  }
};

// Vertices at the same position become one (the first of them, in file order); triangles are
// renumbered, their corners' order kept. Test ModelReader.AnStlsRepeatedCornersAreJoined.
void weld_vertices(Triangle_mesh& mesh) {
  const std::size_t n = mesh.vertices.size();
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  auto less = [&](int a, int b) {
    const Point_3& p = mesh.vertices[static_cast<std::size_t>(a)];
    const Point_3& q = mesh.vertices[static_cast<std::size_t>(b)];
    if (p.x() != q.x()) return p.x() < q.x();
    if (p.y() != q.y()) return p.y() < q.y();
    if (p.z() != q.z()) return p.z() < q.z();
    return a < b;
  };
  std::sort(order.begin(), order.end(), less);
  // Each vertex's representative: the first (smallest index) of its position's run.
  std::vector<int> first(n);
  for (std::size_t i = 0; i < n;) {
    std::size_t j = i;
    while (j < n && mesh.vertices[static_cast<std::size_t>(order[j])] == mesh.vertices[static_cast<std::size_t>(order[i])]) ++j;
    for (std::size_t k = i; k < j; ++k) first[static_cast<std::size_t>(order[k])] = order[i];
    i = j;
  }
  // Kept vertices in file order, renumbered.
  std::vector<int> renumber(n, -1);
  std::vector<Point_3> kept;
  kept.reserve(n);
  for (std::size_t v = 0; v < n; ++v)
    if (first[v] == static_cast<int>(v)) {
      renumber[v] = static_cast<int>(kept.size());
      kept.push_back(mesh.vertices[v]);
    }
  for (auto& t : mesh.triangles)
    for (int& k : t) k = renumber[static_cast<std::size_t>(first[static_cast<std::size_t>(k)])];
  kept.shrink_to_fit();
  mesh.vertices = std::move(kept);
}

}  // namespace

void read_mesh(const std::string& path, const std::string* bytes, const Read_options& options,
               Model& model) {
  Assimp::Importer importer;
  // Points and lines are counted and reported, not read as triangles.
  // Corners at the same position are joined below (weld_vertices), by position only: assimp's
  // JoinIdenticalVertices also compares normals (so STL corners stay apart) and holds about
  // 800 bytes a triangle while it runs.
  const unsigned flags = aiProcess_Triangulate;
  const aiScene* scene = nullptr;
  const std::string ext = lower_ext(path);
  if (bytes)
    scene = importer.ReadFileFromMemory(bytes->data(), bytes->size(), flags, ext.c_str());
  else
    scene = importer.ReadFile(path, flags);
  if (!scene) {
    std::string why = importer.GetErrorString();
    if (why.empty()) why = "unknown format";
    throw Invalid_input(path + ": not a readable CAD or mesh file (assimp: " + why + ")");
  }
  if (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE)
    model.warnings.push_back(path + ": assimp marks the scene incomplete");

  // Units: glTF is in metres by its specification; FBX declares a unit (in centimetres); the rest
  // carry none.
  std::string file_unit = options.unitless_file_unit;
  double scale = 0.0;
  if (ext == "gltf" || ext == "glb") {
    file_unit = "m";
    model.file_unit = "m (glTF)";
  } else if (scene->mMetaData) {
    double f = 0.0;
    float ff = 0.0f;
    if (scene->mMetaData->Get("UnitScaleFactor", f) && f > 0.0 && std::isfinite(f))
      scale = f * 10.0 / unit_in_millimetres(options.scene_unit);
    else if (scene->mMetaData->Get("UnitScaleFactor", ff) && ff > 0.0f && std::isfinite(ff))
      scale = ff * 10.0 / unit_in_millimetres(options.scene_unit);
    if (scale > 0.0) {
      std::ostringstream os;
      os << (scale * unit_in_millimetres(options.scene_unit)) << " mm per file unit (declared)";
      model.file_unit = os.str();
    }
  }
  if (!(scale > 0.0)) {
    scale = scene_scale(file_unit, options);
    if (model.file_unit.empty())
      model.file_unit = file_unit + " (assumed: the format carries no unit)";
  }
  model.scale_to_unit = scale;
  std::string fmt = ext;
  std::transform(fmt.begin(), fmt.end(), fmt.begin(), [](unsigned char c) { return std::toupper(c); });
  model.format_name = (fmt.empty() ? std::string("mesh") : fmt) + " mesh (assimp)";

  Body body;
  body.source_name = stem(path);
  Collector col{scene, &body, &model, scale};
  if (scene->mRootNode)
    col.node(scene->mRootNode, aiMatrix4x4(), 0);
  else
    for (unsigned k = 0; k < scene->mNumMeshes; ++k) col.mesh(scene->mMeshes[k], aiMatrix4x4());
  auto report = [&](std::size_t n, const char* what, const char* why) {
    if (n == 0) return;
    std::ostringstream os;
    os << path << ": " << n << " " << what;
    model.skipped.push_back({os.str(), why, "skipped"});
  };
  report(col.skipped_points, "point primitives", "points are not part of a triangle mesh");
  report(col.skipped_lines, "line primitives", "lines are not part of a triangle mesh");
  report(col.bad_faces, "faces with bad vertex indices", "index outside the mesh's vertices");
  if (col.bad_vertices)
    model.warnings.push_back(path + ": " + std::to_string(col.bad_vertices) +
                             " vertices with non-finite coordinates set to the origin");
  weld_vertices(body.mesh);
  if (!body.mesh.empty()) model.bodies.push_back(std::move(body));
}

}  // namespace extremal::io::internal
