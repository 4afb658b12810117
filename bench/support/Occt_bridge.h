// Our NURBS patches and bodies as OpenCASCADE geometry, for the peers in bench/ (OpenCASCADE
// types appear only in io/ and in bench programs that measure it).
#pragma once

// CGAL before OpenCASCADE: OpenCASCADE's Handle macro breaks CGAL's headers.
#include "kernel/Body.h"
#include "kernel/Rigid_pose_3.h"

#include <Geom_BSplineCurve.hxx>
#include <Geom_BSplineSurface.hxx>
#include <TopoDS_Shape.hxx>

namespace extremal::bench {

// The same poles, knots and weights as a Geom_BSplineSurface, placed by X (control points
// mapped: exact for a rigid map).
Handle(Geom_BSplineSurface) to_occt(const Nurbs_surface_3& s, const Rigid_pose_3& X);

// The same poles, knots and weights as a Geom_BSplineCurve, in its own frame.
Handle(Geom_BSplineCurve) to_occt(const Nurbs_curve_3& c);

// `s` placed by X (a copy of its geometry; BRepBuilderAPI_Transform).
TopoDS_Shape moved(const TopoDS_Shape& s, const Rigid_pose_3& X);

// A compound of one untrimmed face per face of `b` (BRepBuilderAPI_MakeFace, tolerance 1e-7),
// placed by X.
TopoDS_Shape to_occt_shape(const Body& b, const Rigid_pose_3& X);

}  // namespace extremal::bench
