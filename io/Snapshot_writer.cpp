// Tessellation of posed bodies and export through assimp. Every assimp type stays in this file.
#include "io/Snapshot_writer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <assimp/Exporter.hpp>
#include <assimp/material.h>
#include <assimp/scene.h>

#include "kernel/Error.h"

namespace extremal::io {

namespace {

using Vb = CGAL::Triangulation_vertex_base_with_info_2<int, Kernel>;
using Fb = CGAL::Constrained_triangulation_face_base_2<Kernel>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
using Cdt = CGAL::Constrained_Delaunay_triangulation_2<Kernel, Tds, CGAL::Exact_predicates_tag>;
using Point_2 = Kernel::Point_2;

// Triangles of one body in the world frame, with outward normals.
struct Tessellation {
  std::vector<Vec3> points, normals;
  std::vector<std::array<unsigned, 3>> triangles;
};

int spans(const std::vector<double>& knots, double lo, double hi) {
  int n = 0;
  for (std::size_t i = 1; i < knots.size(); ++i)
    if (knots[i] > knots[i - 1] && knots[i - 1] >= lo && knots[i] <= hi) ++n;
  return std::max(n, 1);
}

// Adds the point and outward normal at (u, v); a vanishing normal (a pole, a collapsed edge)
// is taken a little way towards the middle of the patch.
unsigned add_vertex(Tessellation& t, const Face& face, const Rigid_pose_3& pose, double u,
                    double v) {
  const Nurbs_surface_3& s = face.surface;
  u = std::clamp(u, s.u_min(), s.u_max());
  v = std::clamp(v, s.v_min(), s.v_max());
  Surface_point sp;
  s.evaluate(u, v, sp, 1);
  Vec3 n = s.outward_normal(sp);
  for (double step = 1e-6; n.isZero(0.0) && step < 0.2; step *= 10.0) {
    const double um = 0.5 * (s.u_min() + s.u_max()), vm = 0.5 * (s.v_min() + s.v_max());
    Surface_point q;
    s.evaluate(u + (um - u) * step, v + (vm - v) * step, q, 1);
    n = s.outward_normal(q);
  }
  t.points.push_back(pose.apply_point(sp.p));
  t.normals.push_back(pose.apply_vector(n));
  return static_cast<unsigned>(t.points.size() - 1);
}

// Counterclockwise in (u, v) is along f_u x f_v: flip when that points inwards. Triangles
// with no area (at a collapsed patch edge, a pole) are left out.
void add_triangle(Tessellation& t, const Face& face, unsigned a, unsigned b, unsigned c) {
  const Vec3 ab = t.points[b] - t.points[a], ac = t.points[c] - t.points[a];
  const double longest =
      std::max({ab.squaredNorm(), ac.squaredNorm(), (t.points[c] - t.points[b]).squaredNorm()});
  if (!(ab.cross(ac).norm() > 1e-12 * longest)) return;
  if (face.surface.outward_sign() > 0)
    t.triangles.push_back({a, b, c});
  else
    t.triangles.push_back({a, c, b});
}

void tessellate_face(Tessellation& t, const Face& face, const Rigid_pose_3& pose, int per_span) {
  const Nurbs_surface_3& s = face.surface;
  const bool trimmed = !face.trims.empty() && face.trim_region.is_trimmed();
  double u0 = s.u_min(), u1 = s.u_max(), v0 = s.v_min(), v1 = s.v_max();
  if (trimmed) {
    u0 = std::max(u0, face.trim_region.u_min());
    u1 = std::min(u1, face.trim_region.u_max());
    v0 = std::max(v0, face.trim_region.v_min());
    v1 = std::min(v1, face.trim_region.v_max());
    if (!(u0 < u1 && v0 < v1)) return;
  }
  const int nu = std::clamp(per_span * spans(s.knots_u(), u0, u1), 8, 96);
  const int nv = std::clamp(per_span * spans(s.knots_v(), v0, v1), 8, 96);
  auto grid_u = [&](int i) { return i == nu ? u1 : u0 + (u1 - u0) * i / nu; };
  auto grid_v = [&](int j) { return j == nv ? v1 : v0 + (v1 - v0) * j / nv; };

  if (!trimmed) {
    const unsigned first = static_cast<unsigned>(t.points.size());
    for (int i = 0; i <= nu; ++i)
      for (int j = 0; j <= nv; ++j) add_vertex(t, face, pose, grid_u(i), grid_v(j));
    auto at = [&](int i, int j) { return first + static_cast<unsigned>(i * (nv + 1) + j); };
    for (int i = 0; i < nu; ++i)
      for (int j = 0; j < nv; ++j) {
        add_triangle(t, face, at(i, j), at(i + 1, j), at(i + 1, j + 1));
        add_triangle(t, face, at(i, j), at(i + 1, j + 1), at(i, j + 1));
      }
    return;
  }

  // Trimmed: the loops, flattened finely, are constraints; grid points strictly inside the trim
  // fill the interior; triangles whose centre is outside the trim are dropped.
  Cdt cdt;
  for (const Trim_loop& loop : face.trims) {
    Cdt::Vertex_handle first, previous;
    for (const Trim_curve& tc : loop.curves) {
      const Nurbs_curve_3& c = tc.uv;
      const int samples = std::max(8, 4 * c.number_of_poles());
      for (int k = 0; k <= samples; ++k) {
        const int kk = tc.reversed ? samples - k : k;
        const double par = kk == samples
                               ? c.domain_max()
                               : c.domain_min() + (c.domain_max() - c.domain_min()) * kk / samples;
        const Point_3 q = c.point(par);
        const Cdt::Vertex_handle vh = cdt.insert(Point_2(q.x(), q.y()));
        if (first == Cdt::Vertex_handle()) first = vh;
        if (previous != Cdt::Vertex_handle() && previous != vh) cdt.insert_constraint(previous, vh);
        previous = vh;
      }
    }
    if (previous != Cdt::Vertex_handle() && first != Cdt::Vertex_handle() && previous != first)
      cdt.insert_constraint(previous, first);
  }
  for (int i = 1; i < nu; ++i)
    for (int j = 1; j < nv; ++j)
      if (face.trim_region.locate(grid_u(i), grid_v(j)) == Trim_location::Inside)
        cdt.insert(Point_2(grid_u(i), grid_v(j)));

  for (auto vh : cdt.finite_vertex_handles())
    vh->info() = static_cast<int>(add_vertex(t, face, pose, vh->point().x(), vh->point().y()));
  for (auto fh : cdt.finite_face_handles()) {
    const Point_2& a = fh->vertex(0)->point();
    const Point_2& b = fh->vertex(1)->point();
    const Point_2& c = fh->vertex(2)->point();
    const double cu = (a.x() + b.x() + c.x()) / 3.0, cv = (a.y() + b.y() + c.y()) / 3.0;
    if (!face.contains(cu, cv)) continue;
    add_triangle(t, face, static_cast<unsigned>(fh->vertex(0)->info()),
                 static_cast<unsigned>(fh->vertex(1)->info()),
                 static_cast<unsigned>(fh->vertex(2)->info()));
  }
}

Tessellation tessellate(const Body& body, const Rigid_pose_3& pose, int per_span) {
  Tessellation t;
  for (const Face& f : body.faces) tessellate_face(t, f, pose, per_span);
  const unsigned first = static_cast<unsigned>(t.points.size());
  for (const Point_3& p : body.mesh.vertices) {
    t.points.push_back(pose.apply_point(to_vec3(p)));
    t.normals.push_back(Vec3::Zero());
  }
  const int nv = static_cast<int>(body.mesh.vertices.size());
  for (const auto& tri : body.mesh.triangles) {
    if (std::any_of(tri.begin(), tri.end(), [&](int k) { return k < 0 || k >= nv; })) continue;
    t.triangles.push_back({first + static_cast<unsigned>(tri[0]),
                           first + static_cast<unsigned>(tri[1]),
                           first + static_cast<unsigned>(tri[2])});
    // Mesh vertices take the normal of their triangles (area weighted).
    const Vec3 n = (t.points[first + tri[1]] - t.points[first + tri[0]])
                       .cross(t.points[first + tri[2]] - t.points[first + tri[0]]);
    for (int k : tri) t.normals[first + k] += n;
  }
  for (Vec3& n : t.normals)
    if (n.norm() > 0.0) n.normalize();
  return t;
}

aiVector3D to_ai(const Vec3& v) {
  return aiVector3D(static_cast<ai_real>(v.x()), static_cast<ai_real>(v.y()),
                    static_cast<ai_real>(v.z()));
}

aiMaterial* material(const std::string& name, const aiColor4D& colour) {
  auto* m = new aiMaterial();
  const aiString n(name);
  m->AddProperty(&n, AI_MATKEY_NAME);
  m->AddProperty(&colour, 1, AI_MATKEY_COLOR_DIFFUSE);
  m->AddProperty(&colour, 1, AI_MATKEY_BASE_COLOR);
  return m;
}

// The snapshot as an assimp scene; `path` names it in errors (the file, or "snapshot").
std::unique_ptr<aiScene> snapshot_scene(const std::string& path,
                                        const std::vector<Snapshot_body>& bodies,
                                        const std::vector<Snapshot_segment>& segments,
                                        const Snapshot_options& options) {
  for (std::size_t k = 0; k < bodies.size(); ++k)
    if (!bodies[k].body || bodies[k].name.empty())
      throw Invalid_input(path + ": snapshot body " + std::to_string(k) +
                          (bodies[k].body ? " has no name" : " is null"));
  if (!(options.unit_in_metres > 0.0) || !std::isfinite(options.unit_in_metres))
    throw Invalid_input(path + ": snapshot unit_in_metres must be finite and > 0");

  // A few distinct colours for the bodies, red for the witness segments.
  const aiColor4D palette[] = {{0.55f, 0.65f, 0.80f, 1.f}, {0.85f, 0.70f, 0.40f, 1.f},
                               {0.60f, 0.80f, 0.55f, 1.f}, {0.75f, 0.60f, 0.80f, 1.f}};
  auto scene = std::make_unique<aiScene>();
  scene->mFlags = AI_SCENE_FLAGS_NON_VERBOSE_FORMAT;
  scene->mRootNode = new aiNode("scene");
  const ai_real s = static_cast<ai_real>(options.unit_in_metres);
  // (x, y, z) -> s (x, z, -y): z up to glTF's y up, scene unit to metres.
  scene->mRootNode->mTransformation = aiMatrix4x4(s, 0, 0, 0, 0, 0, s, 0, 0, -s, 0, 0, 0, 0, 0, 1);

  std::vector<aiMesh*> meshes;
  std::vector<aiNode*> nodes;
  std::vector<aiMaterial*> materials;
  for (std::size_t k = 0; k < bodies.size(); ++k) {
    const Snapshot_body& sb = bodies[k];
    auto* node = new aiNode(sb.name);
    nodes.push_back(node);
    if (sb.body->is_point) {
      const Vec3 p = sb.pose.translation();
      node->mTransformation.a4 = static_cast<ai_real>(p.x());
      node->mTransformation.b4 = static_cast<ai_real>(p.y());
      node->mTransformation.c4 = static_cast<ai_real>(p.z());
    }
    const Tessellation t = tessellate(*sb.body, sb.pose, options.cells_per_span);
    if (t.triangles.empty()) continue;
    auto* mesh = new aiMesh();
    mesh->mName = aiString(sb.name);
    mesh->mPrimitiveTypes = aiPrimitiveType_TRIANGLE;
    mesh->mNumVertices = static_cast<unsigned>(t.points.size());
    mesh->mVertices = new aiVector3D[mesh->mNumVertices];
    mesh->mNormals = new aiVector3D[mesh->mNumVertices];
    for (unsigned i = 0; i < mesh->mNumVertices; ++i) {
      mesh->mVertices[i] = to_ai(t.points[i]);
      mesh->mNormals[i] = to_ai(t.normals[i]);
    }
    mesh->mNumFaces = static_cast<unsigned>(t.triangles.size());
    mesh->mFaces = new aiFace[mesh->mNumFaces];
    for (unsigned i = 0; i < mesh->mNumFaces; ++i) {
      mesh->mFaces[i].mNumIndices = 3;
      mesh->mFaces[i].mIndices = new unsigned[3]{t.triangles[i][0], t.triangles[i][1],
                                                 t.triangles[i][2]};
    }
    mesh->mMaterialIndex = static_cast<unsigned>(materials.size());
    materials.push_back(material(sb.name, palette[k % 4]));
    node->mNumMeshes = 1;
    node->mMeshes = new unsigned[1]{static_cast<unsigned>(meshes.size())};
    meshes.push_back(mesh);
  }
  if (!segments.empty()) {
    const unsigned red = static_cast<unsigned>(materials.size());
    materials.push_back(material("witness", aiColor4D(0.9f, 0.1f, 0.1f, 1.f)));
    for (const Snapshot_segment& seg : segments) {
      auto* node = new aiNode(seg.name);
      nodes.push_back(node);
      auto* mesh = new aiMesh();
      mesh->mName = aiString(seg.name);
      mesh->mPrimitiveTypes = aiPrimitiveType_LINE;
      mesh->mNumVertices = 2;
      mesh->mVertices = new aiVector3D[2]{to_ai(seg.a), to_ai(seg.b)};
      mesh->mNumFaces = 1;
      mesh->mFaces = new aiFace[1];
      mesh->mFaces[0].mNumIndices = 2;
      mesh->mFaces[0].mIndices = new unsigned[2]{0, 1};
      mesh->mMaterialIndex = red;
      node->mNumMeshes = 1;
      node->mMeshes = new unsigned[1]{static_cast<unsigned>(meshes.size())};
      meshes.push_back(mesh);
    }
  }
  if (materials.empty()) materials.push_back(material("default", palette[0]));

  scene->mNumMeshes = static_cast<unsigned>(meshes.size());
  scene->mMeshes = new aiMesh*[meshes.size()];
  std::copy(meshes.begin(), meshes.end(), scene->mMeshes);
  scene->mNumMaterials = static_cast<unsigned>(materials.size());
  scene->mMaterials = new aiMaterial*[materials.size()];
  std::copy(materials.begin(), materials.end(), scene->mMaterials);
  scene->mRootNode->mNumChildren = static_cast<unsigned>(nodes.size());
  scene->mRootNode->mChildren = new aiNode*[nodes.size()];
  for (std::size_t k = 0; k < nodes.size(); ++k) {
    nodes[k]->mParent = scene->mRootNode;
    scene->mRootNode->mChildren[k] = nodes[k];
  }

  return scene;
}

}  // namespace

void write_snapshot_glb(const std::string& path, const std::vector<Snapshot_body>& bodies,
                        const std::vector<Snapshot_segment>& segments,
                        const Snapshot_options& options) {
  const std::unique_ptr<aiScene> scene = snapshot_scene(path, bodies, segments, options);
  Assimp::Exporter exporter;
  if (exporter.Export(scene.get(), "glb2", path) != aiReturn_SUCCESS)
    throw Invalid_input(path + ": assimp could not write the glTF snapshot (" +
                        exporter.GetErrorString() + ")");
}

std::string snapshot_glb(const std::vector<Snapshot_body>& bodies,
                         const std::vector<Snapshot_segment>& segments,
                         const Snapshot_options& options) {
  const std::unique_ptr<aiScene> scene = snapshot_scene("snapshot", bodies, segments, options);
  Assimp::Exporter exporter;
  const aiExportDataBlob* blob = exporter.ExportToBlob(scene.get(), "glb2");
  if (!blob)
    throw Invalid_input(std::string("snapshot: assimp could not make the glTF (") +
                        exporter.GetErrorString() + ")");
  // A binary glTF is one blob: its buffers are inside it.
  return std::string(static_cast<const char*>(blob->data), blob->size);
}

}  // namespace extremal::io
