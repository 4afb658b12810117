#include "support/Occt_bridge.h"

#include <vector>

#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_Transform.hxx>
#include <BRep_Builder.hxx>
#include <TColStd_Array1OfInteger.hxx>
#include <TColStd_Array1OfReal.hxx>
#include <TColStd_Array2OfReal.hxx>
#include <TColgp_Array1OfPnt.hxx>
#include <TColgp_Array2OfPnt.hxx>
#include <TopoDS_Compound.hxx>
#include <gp_Trsf.hxx>

namespace extremal::bench {

namespace {

// A clamped knot vector as OpenCASCADE's distinct knots and multiplicities.
void knots_to_occt(const std::vector<double>& k, TColStd_Array1OfReal& knots,
                   TColStd_Array1OfInteger& mults) {
  std::vector<double> u;
  std::vector<int> m;
  for (double x : k) {
    if (!u.empty() && x == u.back()) {
      ++m.back();
    } else {
      u.push_back(x);
      m.push_back(1);
    }
  }
  knots.Resize(1, static_cast<int>(u.size()), false);
  mults.Resize(1, static_cast<int>(u.size()), false);
  for (std::size_t i = 0; i < u.size(); ++i) {
    knots.SetValue(static_cast<int>(i) + 1, u[i]);
    mults.SetValue(static_cast<int>(i) + 1, m[i]);
  }
}

}  // namespace

Handle(Geom_BSplineSurface) to_occt(const Nurbs_surface_3& s, const Rigid_pose_3& X) {
  const int nu = s.number_of_poles_u(), nv = s.number_of_poles_v();
  TColgp_Array2OfPnt poles(1, nu, 1, nv);
  TColStd_Array2OfReal weights(1, nu, 1, nv);
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const Vec3 p = X.apply_point(to_vec3(s.pole(i, j)));
      poles.SetValue(i + 1, j + 1, gp_Pnt(p.x(), p.y(), p.z()));
      weights.SetValue(i + 1, j + 1, s.is_rational() ? s.weight(i, j) : 1.0);
    }
  TColStd_Array1OfReal ku(1, 1), kv(1, 1);
  TColStd_Array1OfInteger mu(1, 1), mv(1, 1);
  knots_to_occt(s.knots_u(), ku, mu);
  knots_to_occt(s.knots_v(), kv, mv);
  return new Geom_BSplineSurface(poles, weights, ku, kv, mu, mv, s.degree_u(), s.degree_v());
}

Handle(Geom_BSplineCurve) to_occt(const Nurbs_curve_3& c) {
  const int n = c.number_of_poles();
  TColgp_Array1OfPnt poles(1, n);
  TColStd_Array1OfReal weights(1, n);
  for (int i = 0; i < n; ++i) {
    const Vec3 p = to_vec3(c.poles()[static_cast<std::size_t>(i)]);
    poles.SetValue(i + 1, gp_Pnt(p.x(), p.y(), p.z()));
    weights.SetValue(i + 1, c.is_rational() ? c.weights()[static_cast<std::size_t>(i)] : 1.0);
  }
  TColStd_Array1OfReal knots(1, 1);
  TColStd_Array1OfInteger mults(1, 1);
  knots_to_occt(c.knots(), knots, mults);
  return new Geom_BSplineCurve(poles, weights, knots, mults, c.degree());
}

TopoDS_Shape moved(const TopoDS_Shape& s, const Rigid_pose_3& X) {
  const Mat3& R = X.rotation();
  const Vec3& p = X.translation();
  gp_Trsf T;
  T.SetValues(R(0, 0), R(0, 1), R(0, 2), p.x(), R(1, 0), R(1, 1), R(1, 2), p.y(), R(2, 0),
              R(2, 1), R(2, 2), p.z());
  return BRepBuilderAPI_Transform(s, T, true).Shape();
}

TopoDS_Shape to_occt_shape(const Body& b, const Rigid_pose_3& X) {
  BRep_Builder builder;
  TopoDS_Compound c;
  builder.MakeCompound(c);
  for (const Face& f : b.faces)
    builder.Add(c, BRepBuilderAPI_MakeFace(to_occt(f.surface, X), 1e-7).Face());
  return c;
}

}  // namespace extremal::bench
