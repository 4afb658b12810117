// STEP, IGES and .brep through OpenCASCADE's data exchange. Every OpenCASCADE type stays in this
// file: the rest of Extremal sees bodies made of our Nurbs_surface_3 and Nurbs_curve_3.
//
// Pipeline per body: the solid (or free shell, or loose faces) is converted as a whole by
// BRepBuilderAPI_NurbsConvert, which turns every surface and curve into a B-spline and recomputes
// the parameter-space curves where the surface's parametrisation changed (cylinders, cones,
// spheres and tori become rational B-splines whose parameter is not the angle), keeping edges
// shared between faces; on B-spline faces the file's parameter-space curves are kept where they
// still fit (Pcurve_keeping_modification). Then each face's B-spline surface, its wires' pcurves
// and the edges' 3D curves are copied into kernel types. Anything that fails is reported, never
// dropped silently.
// Our headers (CGAL) first: OpenCASCADE defines a Handle(...) macro that breaks CGAL's Handle.
#include "io/internal/Readers.h"
#include "kernel/Error.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <new>
#include <sstream>

#include <BRepAdaptor_Surface.hxx>
#include <BRepCheck_Analyzer.hxx>
#include <BRepGProp.hxx>
#include <GProp_GProps.hxx>
#include <Bnd_Box.hxx>
#include <BRepBuilderAPI_NurbsConvert.hxx>
#include <BRepTools_NurbsConvertModification.hxx>
#include <BRepTools.hxx>
#include <BRepTools_WireExplorer.hxx>
#include <BRep_Builder.hxx>
#include <BRep_Tool.hxx>
#include <Extrema_GenLocateExtPS.hxx>
#include <Extrema_POnSurf.hxx>
#include <GeomAPI_ProjectPointOnSurf.hxx>
#include <GeomAdaptor_Surface.hxx>
#include <GeomConvert.hxx>
#include <GeomConvert_ApproxSurface.hxx>
#include <Geom2dConvert.hxx>
#include <Geom2d_BSplineCurve.hxx>
#include <Geom2d_BezierCurve.hxx>
#include <Geom2d_Line.hxx>
#include <Geom2d_TrimmedCurve.hxx>
#include <Geom_BSplineCurve.hxx>
#include <Geom_BSplineSurface.hxx>
#include <Geom_BezierCurve.hxx>
#include <Geom_BezierSurface.hxx>
#include <Geom_Line.hxx>
#include <Geom_RectangularTrimmedSurface.hxx>
#include <Geom_TrimmedCurve.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <IGESCAFControl_Reader.hxx>
#include <IGESControl_Reader.hxx>
#include <IGESData_GlobalSection.hxx>
#include <IGESData_IGESModel.hxx>
#include <Interface_Check.hxx>
#include <Interface_CheckIterator.hxx>
#include <Interface_InterfaceModel.hxx>
#include <Interface_Static.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <Message_PrinterOStream.hxx>
#include <STEPCAFControl_Reader.hxx>
#include <STEPControl_Reader.hxx>
#include <Standard_Failure.hxx>
#include <Standard_OutOfMemory.hxx>
#include <TCollection_AsciiString.hxx>
#include <TCollection_HAsciiString.hxx>
#include <TColStd_SequenceOfAsciiString.hxx>
#include <TDF_Label.hxx>
#include <TDF_LabelSequence.hxx>
#include <TDataStd_Name.hxx>
#include <TDocStd_Document.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopLoc_Location.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Wire.hxx>
#include <Transfer_TransientProcess.hxx>
#include <XCAFApp_Application.hxx>
#include <XCAFDoc_DocumentTool.hxx>
#include <XCAFDoc_ShapeTool.hxx>
#include <XSControl_TransferReader.hxx>
#include <XSControl_WorkSession.hxx>
#include <gp_Trsf.hxx>
#include <gp_Vec2d.hxx>

namespace extremal::io::internal {

namespace {

// OpenCASCADE keeps reader settings in process-wide statics and prints progress to stdout
// (which would corrupt `extremal info --json`): one reader at a time, printers removed once.
std::mutex& occt_mutex() {
  static std::mutex m;
  return m;
}

void quiet_occt() {
  static std::once_flag once;
  std::call_once(once, [] {
    Message::DefaultMessenger()->RemovePrinters(STANDARD_TYPE(Message_PrinterOStream));
  });
}

std::string failure_text(const Standard_Failure& f) {
  std::string s = f.DynamicType()->Name();
  const char* msg = f.GetMessageString();
  if (msg && *msg) s += std::string(": ") + msg;
  return s;
}

std::string surface_kind(GeomAbs_SurfaceType t) {
  switch (t) {
    case GeomAbs_Plane: return "plane";
    case GeomAbs_Cylinder: return "cylinder";
    case GeomAbs_Cone: return "cone";
    case GeomAbs_Sphere: return "sphere";
    case GeomAbs_Torus: return "torus";
    case GeomAbs_BezierSurface: return "bezier";
    case GeomAbs_BSplineSurface: return "bspline";
    case GeomAbs_SurfaceOfRevolution: return "revolution";
    case GeomAbs_SurfaceOfExtrusion: return "extrusion";
    case GeomAbs_OffsetSurface: return "offset";
    default: return "other";
  }
}

// Kinds whose B-spline form is exact (NURBS reproduce planes, quadrics, tori, and revolved or
// extruded conics and B-splines exactly).
bool conversion_is_exact(const std::string& kind) {
  return kind != "offset" && kind != "other";
}

std::string ascii(const TCollection_ExtendedString& s) {
  TCollection_AsciiString a(s, '?');
  return a.ToCString();
}

std::string label_name(const TDF_Label& label) {
  Handle(TDataStd_Name) name;
  if (!label.IsNull() && label.FindAttribute(TDataStd_Name::GetID(), name)) {
    std::string n = ascii(name->Get());
    // XCAF names unnamed instances "=>[0:1:1:3]" (a label reference): no name for us.
    if (n.rfind("=>[", 0) == 0) return {};
    return n;
  }
  return {};
}

Rigid_pose_3 to_pose(const TopLoc_Location& loc, double scale) {
  const gp_Trsf t = loc.Transformation();
  Mat3 R;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) R(i, j) = t.Value(i + 1, j + 1);
  // gp_Trsf may carry a uniform scale factor; a rigid placement cannot: divide it out of the
  // rotation (the caller warns) and keep the translation.
  const double s = std::abs(t.ScaleFactor());
  if (s > 0.0 && std::abs(s - 1.0) > 1e-12) R /= s;
  const gp_XYZ tr = t.TranslationPart();
  return Rigid_pose_3(R, Vec3(tr.X(), tr.Y(), tr.Z()) * scale);
}

// Flat knot vector with multiplicities expanded.
std::vector<double> flat_knots(const TColStd_Array1OfReal& knots,
                               const TColStd_Array1OfInteger& mults) {
  std::vector<double> out;
  for (int i = knots.Lower(); i <= knots.Upper(); ++i)
    for (int m = 0; m < mults(i); ++m) out.push_back(knots(i));
  return out;
}

Nurbs_surface_3 to_nurbs(Handle(Geom_BSplineSurface) bs, double scale) {
  if (bs->IsUPeriodic()) bs->SetUNotPeriodic();
  if (bs->IsVPeriodic()) bs->SetVNotPeriodic();
  const int nu = bs->NbUPoles(), nv = bs->NbVPoles();
  std::vector<Point_3> poles;
  std::vector<double> weights;
  poles.reserve(static_cast<std::size_t>(nu) * nv);
  const bool rational = bs->IsURational() || bs->IsVRational();
  for (int i = 1; i <= nu; ++i)
    for (int j = 1; j <= nv; ++j) {
      const gp_Pnt p = bs->Pole(i, j);
      poles.emplace_back(p.X() * scale, p.Y() * scale, p.Z() * scale);
      if (rational) weights.push_back(bs->Weight(i, j));
    }
  TColStd_Array1OfReal ku(1, bs->NbUKnots()), kv(1, bs->NbVKnots());
  TColStd_Array1OfInteger mu(1, bs->NbUKnots()), mv(1, bs->NbVKnots());
  bs->UKnots(ku);
  bs->VKnots(kv);
  bs->UMultiplicities(mu);
  bs->VMultiplicities(mv);
  return Nurbs_surface_3(bs->UDegree(), bs->VDegree(), nu, nv, std::move(poles),
                         flat_knots(ku, mu), flat_knots(kv, mv), std::move(weights));
}

Nurbs_curve_3 to_nurbs(Handle(Geom_BSplineCurve) bc, double scale) {
  if (bc->IsPeriodic()) bc->SetNotPeriodic();
  std::vector<Point_3> poles;
  std::vector<double> weights;
  for (int i = 1; i <= bc->NbPoles(); ++i) {
    const gp_Pnt p = bc->Pole(i);
    poles.emplace_back(p.X() * scale, p.Y() * scale, p.Z() * scale);
    if (bc->IsRational()) weights.push_back(bc->Weight(i));
  }
  TColStd_Array1OfReal k(1, bc->NbKnots());
  TColStd_Array1OfInteger m(1, bc->NbKnots());
  bc->Knots(k);
  bc->Multiplicities(m);
  return Nurbs_curve_3(bc->Degree(), std::move(poles), flat_knots(k, m), std::move(weights));
}

Nurbs_curve_3 to_nurbs(Handle(Geom2d_BSplineCurve) bc) {
  if (bc->IsPeriodic()) bc->SetNotPeriodic();
  std::vector<Point_3> poles;
  std::vector<double> weights;
  for (int i = 1; i <= bc->NbPoles(); ++i) {
    const gp_Pnt2d p = bc->Pole(i);
    poles.emplace_back(p.X(), p.Y(), 0.0);
    if (bc->IsRational()) weights.push_back(bc->Weight(i));
  }
  TColStd_Array1OfReal k(1, bc->NbKnots());
  TColStd_Array1OfInteger m(1, bc->NbKnots());
  bc->Knots(k);
  bc->Multiplicities(m);
  return Nurbs_curve_3(bc->Degree(), std::move(poles), flat_knots(k, m), std::move(weights));
}

// The B-spline form of curve c over [f, l], keeping c's parameter where c is a B-spline (a
// segment of it) and clamping [f, l] into a non-periodic curve's range (edges may overrun it by
// rounding). Null if nothing works.
Handle(Geom_BSplineCurve) bspline_segment(Handle(Geom_Curve) c, double f, double l) {
  while (auto t = Handle(Geom_TrimmedCurve)::DownCast(c)) c = t->BasisCurve();
  if (!c->IsPeriodic()) {
    f = std::max(f, c->FirstParameter());
    l = std::min(l, c->LastParameter());
  }
  if (!(f < l)) return nullptr;
  if (auto b = Handle(Geom_BSplineCurve)::DownCast(c)) {
    Handle(Geom_BSplineCurve) copy = Handle(Geom_BSplineCurve)::DownCast(b->Copy());
    if (copy->IsPeriodic() || f > copy->FirstParameter() || l < copy->LastParameter())
      copy->Segment(f, l);
    return copy;
  }
  return GeomConvert::CurveToBSplineCurve(new Geom_TrimmedCurve(c, f, l));
}

Handle(Geom2d_BSplineCurve) bspline_segment(Handle(Geom2d_Curve) c, double f, double l) {
  while (auto t = Handle(Geom2d_TrimmedCurve)::DownCast(c)) c = t->BasisCurve();
  if (!c->IsPeriodic()) {
    f = std::max(f, c->FirstParameter());
    l = std::min(l, c->LastParameter());
  }
  if (!(f < l)) return nullptr;
  if (auto b = Handle(Geom2d_BSplineCurve)::DownCast(c)) {
    Handle(Geom2d_BSplineCurve) copy = Handle(Geom2d_BSplineCurve)::DownCast(b->Copy());
    if (copy->IsPeriodic() || f > copy->FirstParameter() || l < copy->LastParameter())
      copy->Segment(f, l);
    return copy;
  }
  return Geom2dConvert::CurveToBSplineCurve(new Geom2d_TrimmedCurve(c, f, l), Convert_RationalC1);
}

bool same_range(double a0, double a1, double b0, double b1) {
  const double tol = 1e-9 * std::max({1.0, std::abs(a0), std::abs(a1)});
  return std::abs(a0 - b0) <= tol && std::abs(a1 - b1) <= tol;
}

// One reading session: the file's transfer process (for entity names) and the model.
struct Session {
  std::string path;
  std::string format_word;  // "STEP", "IGES", "BREP"
  Handle(XSControl_WorkSession) ws;
  const Read_options* options = nullptr;
  const Cad_scan* scan = nullptr;
  double scale = 1.0;  // OCCT lengths (mm) -> scene unit
  Model* model = nullptr;

  // The entity's label in the file: "#20" (STEP: the instance name in the file, not its rank
  // in OpenCASCADE's model) or "D45" (IGES: its directory entry's line). Empty when unknown.
  std::string file_label(const Handle(Standard_Transient)& ent) const {
    if (ent.IsNull() || ws.IsNull() || ws->Model().IsNull()) return {};
    const Handle(TCollection_HAsciiString) l = ws->Model()->StringLabel(ent);
    return l.IsNull() ? std::string() : std::string(l->ToCString());
  }

  // "STEP #20 (StepGeom_BSplineSurfaceWithKnots)", "IGES entity D45 (IGESGeom_BSplineSurface)".
  std::string entity_text(const Handle(Standard_Transient)& ent) const {
    std::string label = file_label(ent);
    if (format_word == "IGES" && !label.empty() && label[0] != 'D') label = "D" + label;
    return (format_word == "IGES" ? "IGES entity " : format_word + " ") + label + " (" +
           ent->DynamicType()->Name() + ")";
  }

  std::string entity_name(const TopoDS_Shape& s, const std::string& fallback) const {
    if (ws.IsNull()) return fallback;
    try {
      Handle(XSControl_TransferReader) tr = ws->TransferReader();
      if (tr.IsNull()) return fallback;
      Handle(Standard_Transient) ent = tr->EntityFromShapeResult(s, 1);
      if (ent.IsNull()) ent = tr->EntityFromShapeResult(s, -1);
      if (ent.IsNull() || file_label(ent).empty()) return fallback;
      return entity_text(ent);
    } catch (const Standard_Failure&) {
      return fallback;
    }
  }

  void skip(const std::string& entity, const std::string& reason, const std::string& action) {
    model->skipped.push_back({entity, reason, action});
  }
};

// Sample grid of the deviation measurement: kDeviationIntervals intervals per direction, one
// more such step per
// kDeviationSpansPerStep knot spans up to kDeviationMaxIntervals, so every span holds samples.
constexpr int kDeviationIntervals = 16;
constexpr int kDeviationSpansPerStep = 4;
constexpr int kDeviationMaxIntervals = 64;

int deviation_intervals(const std::vector<double>& knots, double lo, double hi) {
  int spans = 0;
  for (std::size_t i = 1; i < knots.size(); ++i)
    if (knots[i] > knots[i - 1] && knots[i - 1] >= lo && knots[i] <= hi) ++spans;
  const int steps = std::clamp((spans + kDeviationSpansPerStep - 1) / kDeviationSpansPerStep, 1,
                               kDeviationMaxIntervals / kDeviationIntervals);
  return kDeviationIntervals * steps;
}

// Largest distance from our surface, sampled inside the trim, to the source surface. Each
// sample's value is the distance from our point p = s(u, v) to a point of the source, so it is
// an upper bound of p's distance to the source surface (to rounding, at least what a global
// projection finds): the source at the same (u, v) (approximations keep the parametrisation,
// so that point is already close), lowered by a local minimisation of the distance started
// there (which also finds the foot point where the parametrisation differs, e.g. an offset
// cylinder converted to a rational one); OpenCASCADE's global projection (a grid search per
// point, costly) only where that local search fails.
// Between samples nothing is bounded: a certified margin needs a bound on the derivatives of
// (ours - source), which OpenCASCADE's surfaces do not give, and the distance's Lipschitz
// bound from our control net alone (|s_u| h_u / 2 + |s_v| h_v / 2) is orders of magnitude above
// the deviations measured.
double measure_deviation(const Face& f, const Handle(Geom_Surface)& source, double scale) {
  const Nurbs_surface_3& s = f.surface;
  double su0, su1, sv0, sv1;
  source->Bounds(su0, su1, sv0, sv1);
  GeomAdaptor_Surface adaptor(source);
  Extrema_GenLocateExtPS local(adaptor);
  GeomAPI_ProjectPointOnSurf proj;
  const int nu = deviation_intervals(s.knots_u(), s.u_min(), s.u_max());
  const int nv = deviation_intervals(s.knots_v(), s.v_min(), s.v_max());
  double worst = 0.0;
  for (int i = 0; i <= nu; ++i)
    for (int j = 0; j <= nv; ++j) {
      const double u = std::min(s.u_min() + (s.u_max() - s.u_min()) * i / nu, s.u_max());
      const double v = std::min(s.v_min() + (s.v_max() - s.v_min()) * j / nv, s.v_max());
      if (!f.contains(u, v)) continue;
      const Point_3 q = s.point(u, v);
      const gp_Pnt p(q.x() / scale, q.y() / scale, q.z() / scale);
      const double u0 = std::clamp(u, su0, su1), v0 = std::clamp(v, sv0, sv1);
      double d = std::numeric_limits<double>::infinity();
      bool found = false;
      try {  // an offset surface has no value where its basis has no normal
        d = p.Distance(source->Value(u0, v0));
        local.Perform(p, u0, v0, Standard_True);
        if (local.IsDone()) {
          d = std::min(d, p.Distance(local.Point().Value()));
          found = true;
        }
      } catch (const Standard_Failure&) {
      }
      if (!found) {
        proj.Init(p, source);
        if (proj.NbPoints() > 0) d = std::min(d, proj.LowerDistance());
      }
      if (std::isfinite(d)) worst = std::max(worst, d * scale);
    }
  return worst;
}

// The B-spline surface of a converted face, or an approximation of whatever it is (which keeps
// the parametrisation, so the pcurves stay valid). Null if nothing works.
Handle(Geom_BSplineSurface) bspline_of(const TopoDS_Face& face, double tol, bool& approximated,
                                       double& approx_error) {
  approximated = false;
  approx_error = 0.0;
  Handle(Geom_Surface) s = BRep_Tool::Surface(face);
  if (s.IsNull()) return nullptr;
  Handle(Geom_Surface) basis = s;
  while (auto rt = Handle(Geom_RectangularTrimmedSurface)::DownCast(basis))
    basis = rt->BasisSurface();
  if (auto bs = Handle(Geom_BSplineSurface)::DownCast(basis))
    return Handle(Geom_BSplineSurface)::DownCast(bs->Copy());
  double u0, u1, v0, v1;
  BRepTools::UVBounds(face, u0, u1, v0, v1);
  Handle(Geom_Surface) trimmed = new Geom_RectangularTrimmedSurface(s, u0, u1, v0, v1);
  GeomConvert_ApproxSurface approx(trimmed, tol, GeomAbs_C2, GeomAbs_C2, 14, 14, 200, 0);
  if (!approx.HasResult()) return nullptr;
  approximated = true;
  approx_error = approx.MaxError();
  return approx.Surface();
}

// OpenCASCADE's NURBS conversion, except for the curves on a face whose surface it keeps (B-spline
// and Bezier surfaces are not converted): where the edge's 3D curve keeps its parameter through
// the conversion too (lines, B-spline and Bezier curves, trimmed or not) and the face curve is a
// line, B-spline or Bezier curve (whose B-spline form has the same parameter), the face curve is
// kept as it is if, sampled, it lies on the 3D curve within the edge's tolerance. OpenCASCADE
// instead re-projects the new 3D curve onto the unchanged surface and measures the result
// (ProjLib_ComputeApproxOnPolarSurface, GeomLib_CheckCurveOnSurface): the bulk of the import
// time on B-spline parts, for a curve that approximates the one kept. The kept curve has the
// same surface, 3D curve and parameter as in the file, so the edge's tolerance stays as read
// (convert_shape measures the gap again). Seams, degenerate edges, edges without a 3D curve,
// face curves off their 3D curve and the faces OpenCASCADE converts go through its own code.
// Samples of the face curve against the 3D curve before keeping it (a multiple of the 16
// intervals of convert_shape's edge check, whose samples it contains).
constexpr int kPcurveCheckIntervals = 32;

class Pcurve_keeping_modification : public BRepTools_NurbsConvertModification {
 public:
  Standard_Boolean NewCurve2d(const TopoDS_Edge& e, const TopoDS_Face& f, const TopoDS_Edge& new_e,
                              const TopoDS_Face& new_f, Handle(Geom2d_Curve)& c,
                              Standard_Real& tol) override {
    double first, last;
    Handle(Geom2d_Curve) pc;
    if (keeps_face_curves(f) && keeps_parametrisation(e, f, pc, first, last)) {
      Handle(Geom2d_Curve) basis = pc;
      while (auto t = Handle(Geom2d_TrimmedCurve)::DownCast(basis)) basis = t->BasisCurve();
      if (basis->IsKind(STANDARD_TYPE(Geom2d_Line)))
        c = Geom2dConvert::CurveToBSplineCurve(new Geom2d_TrimmedCurve(basis, first, last));
      else
        c = Handle(Geom2d_Curve)::DownCast(basis->Copy());
      tol = BRep_Tool::Tolerance(e);
      return Standard_True;
    }
    return BRepTools_NurbsConvertModification::NewCurve2d(e, f, new_e, new_f, c, tol);
  }

 private:
  // A face keeps all its curves or none: kept and re-projected curves need not meet at their
  // shared vertices within the trim band (they chain each among their own kind).
  bool keeps_face_curves(const TopoDS_Face& f) {
    const auto known = m_face_keeps.find(f.TShape().get());
    if (known != m_face_keeps.end()) return known->second;
    bool all = true;
    const TopoDS_Face fwd = TopoDS::Face(f.Oriented(TopAbs_FORWARD));
    for (TopExp_Explorer ex(fwd, TopAbs_EDGE); all && ex.More(); ex.Next()) {
      Handle(Geom2d_Curve) pc;
      double first, last;
      all = keeps_parametrisation(TopoDS::Edge(ex.Current()), fwd, pc, first, last);
    }
    m_face_keeps[f.TShape().get()] = all;
    return all;
  }

  std::map<const TopoDS_TShape*, bool> m_face_keeps;

  static bool keeps_parametrisation(const TopoDS_Edge& e, const TopoDS_Face& f,
                                    Handle(Geom2d_Curve)& pc, double& first, double& last) {
    if (BRep_Tool::Degenerated(e) || BRepTools::IsReallyClosed(e, f)) return false;
    const Handle(Geom_Surface) s = BRep_Tool::Surface(f);
    if (s.IsNull() || (s->DynamicType() != STANDARD_TYPE(Geom_BSplineSurface) &&
                       s->DynamicType() != STANDARD_TYPE(Geom_BezierSurface)))
      return false;
    double cf, cl;
    Handle(Geom_Curve) c3 = BRep_Tool::Curve(e, cf, cl);
    if (c3.IsNull()) return false;
    while (auto t = Handle(Geom_TrimmedCurve)::DownCast(c3)) c3 = t->BasisCurve();
    if (!c3->IsKind(STANDARD_TYPE(Geom_Line)) && !c3->IsKind(STANDARD_TYPE(Geom_BSplineCurve)) &&
        !c3->IsKind(STANDARD_TYPE(Geom_BezierCurve)))
      return false;
    pc = BRep_Tool::CurveOnSurface(e, f, first, last);
    if (pc.IsNull() || !(first < last)) return false;
    Handle(Geom2d_Curve) basis = pc;
    while (auto t = Handle(Geom2d_TrimmedCurve)::DownCast(basis)) basis = t->BasisCurve();
    if (!basis->IsKind(STANDARD_TYPE(Geom2d_Line)) &&
        !basis->IsKind(STANDARD_TYPE(Geom2d_BSplineCurve)) &&
        !basis->IsKind(STANDARD_TYPE(Geom2d_BezierCurve)))
      return false;
    // The face curve must lie on the 3D curve within the edge's tolerance: face curves that
    // OpenCASCADE made on reading (files without them) can stray further, and its projection
    // does better there. Sampled at a superset of convert_shape's check of the same gap.
    const double tol = BRep_Tool::Tolerance(e);
    for (int k = 0; k <= kPcurveCheckIntervals; ++k) {
      const double t = first + (last - first) * k / kPcurveCheckIntervals;
      const gp_Pnt2d uv = pc->Value(t);
      if (s->Value(uv.X(), uv.Y()).Distance(c3->Value(std::clamp(t, cf, cl))) > tol) return false;
    }
    return true;
  }
};

// BRepBuilderAPI_NurbsConvert (its vertex tolerance correction included) with the modification
// above.
class Nurbs_convert : public BRepBuilderAPI_NurbsConvert {
 public:
  explicit Nurbs_convert(const TopoDS_Shape& shape) {
    myModification = new Pcurve_keeping_modification();
    Perform(shape, Standard_True);
  }
};

// Converts one OCCT shape (a solid, a shell or a compound of faces) into a body. Faces that
// cannot be converted are reported and left out; the body keeps the rest.
Body convert_shape(const TopoDS_Shape& shape, Session& ss, const std::string& body_label) {
  Body body;
  const double scale = ss.scale;
  TopoDS_Shape converted;
  std::unique_ptr<Nurbs_convert> whole;
  try {
    whole = std::make_unique<Nurbs_convert>(shape);
    if (!whole->IsDone()) whole.reset();
  } catch (const Standard_Failure& e) {
    ss.model->warnings.push_back(body_label + ": B-spline conversion of the whole shape failed (" +
                                 failure_text(e) + "), converting face by face");
    whole.reset();
  }

  TopTools_IndexedMapOfShape edge_index;  // converted edges -> Body::edges
  int face_no = 0;
  for (TopExp_Explorer fx(shape, TopAbs_FACE); fx.More(); fx.Next()) {
    ++face_no;
    const TopoDS_Face src = TopoDS::Face(fx.Current());
    std::ostringstream fallback;
    fallback << "face " << face_no << " of " << body_label;
    auto name = [&]() { return ss.entity_name(src, fallback.str()); };
    try {
      const std::string kind = surface_kind(BRepAdaptor_Surface(src, Standard_False).GetType());
      TopoDS_Face nf;
      std::unique_ptr<Nurbs_convert> single;
      if (whole) {
        nf = TopoDS::Face(whole->ModifiedShape(src));
      } else {
        single = std::make_unique<Nurbs_convert>(src);
        nf = TopoDS::Face(single->Shape());
      }
      nf.Orientation(src.Orientation());

      double u0, u1, v0, v1;
      BRepTools::UVBounds(nf, u0, u1, v0, v1);
      Handle(Geom_Surface) src_surface = BRep_Tool::Surface(src);
      bool approximated = false;
      double approx_err = 0.0;
      double size = 1.0;
      {
        Bnd_Box b;
        for (TopExp_Explorer vx(nf, TopAbs_VERTEX); vx.More(); vx.Next())
          b.Add(BRep_Tool::Pnt(TopoDS::Vertex(vx.Current())));
        if (!b.IsVoid()) {
          double x0, y0, z0, x1, y1, z1;
          b.Get(x0, y0, z0, x1, y1, z1);
          size = std::max({x1 - x0, y1 - y0, z1 - z0, 1e-3});
        }
      }
      Handle(Geom_BSplineSurface) bs =
          bspline_of(nf, ss.options->approximation_tolerance * size, approximated, approx_err);
      if (bs.IsNull()) {
        ss.skip(name(), kind + " surface has no B-spline form and could not be approximated",
                "skipped");
        continue;
      }
      // A periodic surface's trims may straddle its first period (a torus trimmed to
      // u in [-pi/2, pi/2] on [0, 2 pi]): cut the periodic directions to the face's parameter
      // range, which keeps the parametrisation and gives a clamped patch holding every trim.
      double shift_u = 0.0, shift_v = 0.0;
      if (bs->IsUPeriodic() || bs->IsVPeriodic()) {
        double s0, s1, t0, t1;
        bs->Bounds(s0, s1, t0, t1);
        double a0 = u0, a1 = u1, b0 = v0, b1 = v1;
        if (!bs->IsUPeriodic()) a0 = s0, a1 = s1;
        if (!bs->IsVPeriodic()) b0 = t0, b1 = t1;
        if (bs->IsUPeriodic() && a1 - a0 > bs->UPeriod()) a1 = a0 + bs->UPeriod();
        if (bs->IsVPeriodic() && b1 - b0 > bs->VPeriod()) b1 = b0 + bs->VPeriod();
        const bool inside = a0 >= s0 && a1 <= s1 && b0 >= t0 && b1 <= t1;
        if (!inside && a0 < a1 && b0 < b1) {
          const double up = bs->IsUPeriodic() ? bs->UPeriod() : 0.0;
          const double vp = bs->IsVPeriodic() ? bs->VPeriod() : 0.0;
          bs->Segment(a0, a1, b0, b1);
          // Segment moves the range into the first period: the trims follow by whole periods.
          double n0, n1, m0, m1;
          bs->Bounds(n0, n1, m0, m1);
          if (up > 0.0) shift_u = std::round((n0 - a0) / up) * up;
          if (vp > 0.0) shift_v = std::round((m0 - b0) / vp) * vp;
        }
      }
      Face face(to_nurbs(bs, scale), kind);
      face.surface.set_outward_sign(nf.Orientation() == TopAbs_REVERSED ? -1 : 1);
      face.source = name();

      // Trim loops, from the face taken FORWARD so that loops keep the file's orientation
      // (material on the left); the surface's outward_sign carries the face orientation.
      const TopoDS_Face fwd = TopoDS::Face(nf.Oriented(TopAbs_FORWARD));
      const TopoDS_Wire outer = BRepTools::OuterWire(fwd);
      const int face_index = static_cast<int>(body.faces.size());
      // Edge uses are committed with the face, so a face that fails leaves no stale use.
      std::vector<std::pair<int, Edge_use>> pending_uses;
      bool trims_ok = true;
      for (TopExp_Explorer wx(fwd, TopAbs_WIRE); wx.More(); wx.Next()) {
        const TopoDS_Wire w = TopoDS::Wire(wx.Current());
        Trim_loop loop;
        loop.is_outer = w.IsSame(outer);
        std::vector<TopoDS_Edge> edges;
        for (BRepTools_WireExplorer we(w, fwd); we.More(); we.Next()) edges.push_back(we.Current());
        int n_in_wire = 0;
        for (TopExp_Explorer ex(w, TopAbs_EDGE); ex.More(); ex.Next()) ++n_in_wire;
        if (static_cast<int>(edges.size()) != n_in_wire) {
          // Wire explorer could not order the edges (a broken wire): take them as stored.
          edges.clear();
          for (TopExp_Explorer ex(w, TopAbs_EDGE); ex.More(); ex.Next())
            edges.push_back(TopoDS::Edge(ex.Current()));
          ss.model->warnings.push_back(face.source + ": a wire's edges do not chain; kept as stored");
        }
        for (const TopoDS_Edge& e : edges) {
          double f, l;
          Handle(Geom2d_Curve) pc = BRep_Tool::CurveOnSurface(e, fwd, f, l);
          if (pc.IsNull() || !(f < l)) {
            trims_ok = false;
            continue;
          }
          Handle(Geom2d_BSplineCurve) b2 = bspline_segment(pc, f, l);
          if (b2.IsNull()) {
            trims_ok = false;
            continue;
          }
          if (shift_u != 0.0 || shift_v != 0.0) b2->Translate(gp_Vec2d(shift_u, shift_v));
          Trim_curve tc{to_nurbs(b2), -1, e.Orientation() == TopAbs_REVERSED};
          const bool uv_same = same_range(tc.uv.domain_min(), tc.uv.domain_max(), f, l);

          // The shared edge record.
          const int idx = edge_index.FindIndex(e);
          int edge_id;
          if (idx == 0) {
            edge_id = edge_index.Add(e) - 1;
            Edge edge;
            edge.t_min = f;
            edge.t_max = l;
            edge.tolerance = BRep_Tool::Tolerance(e) * scale;
            edge.same_parameter = BRep_Tool::SameParameter(e) && uv_same;
            edge.degenerate = BRep_Tool::Degenerated(e);
            double cf, cl;
            Handle(Geom_Curve) c3 = edge.degenerate ? nullptr : BRep_Tool::Curve(e, cf, cl);
            if (!c3.IsNull() && cf < cl) {
              Handle(Geom_BSplineCurve) b3 = bspline_segment(c3, cf, cl);
              if (!b3.IsNull()) {
                edge.curve = to_nurbs(b3, scale);
                if (!same_range(edge.curve->domain_min(), edge.curve->domain_max(), f, l))
                  edge.same_parameter = false;
              }
            }
            body.edges.push_back(std::move(edge));
          } else {
            edge_id = idx - 1;
            const Edge& known = body.edges[edge_id];
            if (!uv_same || !same_range(known.t_min, known.t_max, f, l))
              body.edges[edge_id].same_parameter = false;
          }
          tc.edge = edge_id;
          pending_uses.emplace_back(
              edge_id, Edge_use{face_index, static_cast<int>(face.trims.size()),
                                static_cast<int>(loop.curves.size())});
          loop.curves.push_back(std::move(tc));
        }
        if (!loop.curves.empty()) face.trims.push_back(std::move(loop));
      }
      if (!trims_ok)
        ss.model->warnings.push_back(face.source +
                                     ": an edge has no usable curve on the face; its loop is "
                                     "closed by a straight segment");
      const double extent = std::max(face.surface.u_max() - face.surface.u_min(),
                                     face.surface.v_max() - face.surface.v_min());
      face.update_trim_region(ss.options->trim_tolerance * extent);
      if (!face.trim_region.is_closed())
        ss.model->warnings.push_back(face.source + ": a trim loop does not close");
      if (approximated || !conversion_is_exact(kind)) {
        face.approximation_error =
            std::max(approx_err * scale, measure_deviation(face, src_surface, scale));
        std::ostringstream os;
        os << face.source << ": " << kind << " surface has no exact NURBS form; approximated, "
           << "deviation " << face.approximation_error << " " << ss.model->unit;
        ss.model->warnings.push_back(os.str());
      }
      body.faces.push_back(std::move(face));
      for (const auto& [id, use] : pending_uses) body.edges[id].uses.push_back(use);
    } catch (const Standard_Failure& e) {
      ss.skip(name(), "OpenCASCADE failed: " + failure_text(e), "skipped");
    } catch (const Invalid_input& e) {
      ss.skip(name(), e.what(), "skipped");
    }
  }
  // Measured agreement of every use's uv curve, mapped on its face, with the 3D curve at the
  // same parameter: the edge tolerance we publish is at least that (files are often looser
  // than their declared tolerances, and the B-spline conversion recomputes some pcurves).
  int loosened = 0;
  double worst = 0.0;
  for (auto& e : body.edges) {
    if (!e.curve || !e.same_parameter) continue;
    double dev = 0.0;
    for (const Edge_use& use : e.uses) {
      if (use.face >= static_cast<int>(body.faces.size())) continue;
      const Face& f = body.faces[use.face];
      const Nurbs_curve_3& uv = f.trims[use.loop].curves[use.curve].uv;
      const Nurbs_surface_3& s = f.surface;
      for (int k = 0; k <= 16; ++k) {
        const double t = std::min(e.t_min + (e.t_max - e.t_min) * k / 16.0, e.t_max);
        const Point_3 q = uv.point(std::clamp(t, uv.domain_min(), uv.domain_max()));
        const Point_3 p = s.point(std::clamp(q.x(), s.u_min(), s.u_max()),
                                  std::clamp(q.y(), s.v_min(), s.v_max()));
        const Point_3 c = e.curve->point(std::clamp(t, e.curve->domain_min(), e.curve->domain_max()));
        dev = std::max(dev, (to_vec3(p) - to_vec3(c)).norm());
      }
    }
    if (dev > e.tolerance) {
      if (dev > 1.01 * e.tolerance + 1e-12) ++loosened;
      worst = std::max(worst, dev);
      e.tolerance = dev;
    }
  }
  if (loosened > 0) {
    std::ostringstream os;
    os << body_label << ": " << loosened << " edges' face curves deviate from the 3D curve by "
       << "more than the file's tolerance (up to " << worst << "); their tolerance is raised";
    ss.model->warnings.push_back(os.str());
  }

  return body;
}

// What OpenCASCADE says about a solid as read (after the reader's own shape healing, which
// already re-orients misoriented faces): a valid shape (BRepCheck), a closed and consistently
// oriented boundary, a positive volume (a solid whose faces all point inwards passes the other
// checks). Anything else is a warning naming the solid.
void check_solid(const TopoDS_Shape& solid, const std::string& label, Session& ss) {
  try {
    BRepCheck_Analyzer analyzer(solid);
    if (!analyzer.IsValid())
      ss.model->warnings.push_back(label +
                                   ": OpenCASCADE's shape check (BRepCheck) finds the shape invalid");
    // Every edge of a closed, consistently oriented boundary is used by its faces once
    // forward and once reversed (a seam by its one face both ways).
    TopTools_IndexedMapOfShape edges;
    std::vector<int> forward, reversed;
    for (TopExp_Explorer fx(solid, TopAbs_FACE); fx.More(); fx.Next())
      for (TopExp_Explorer ex(fx.Current(), TopAbs_EDGE); ex.More(); ex.Next()) {
        const TopoDS_Edge& e = TopoDS::Edge(ex.Current());
        if (BRep_Tool::Degenerated(e)) continue;
        const int k = edges.Add(e) - 1;
        forward.resize(edges.Extent(), 0);
        reversed.resize(edges.Extent(), 0);
        if (e.Orientation() == TopAbs_FORWARD) ++forward[k];
        if (e.Orientation() == TopAbs_REVERSED) ++reversed[k];
      }
    int free_edges = 0, misoriented = 0;
    for (int k = 0; k < edges.Extent(); ++k) {
      if (forward[k] + reversed[k] < 2) ++free_edges;
      else if (forward[k] != 1 || reversed[k] != 1) ++misoriented;
    }
    if (free_edges > 0) {
      ss.model->warnings.push_back(label + ": the boundary is not closed (" +
                                   std::to_string(free_edges) + " edges bound only one face)");
      return;  // no volume to check
    }
    if (misoriented > 0)
      ss.model->warnings.push_back(label + ": the faces are not consistently oriented (" +
                                   std::to_string(misoriented) +
                                   " edges are not used once each way)");
    if (solid.ShapeType() != TopAbs_SOLID) return;
    GProp_GProps props;
    BRepGProp::VolumeProperties(solid, props);
    if (!(props.Mass() > 0.0)) {
      std::ostringstream os;
      os << label << ": the solid's volume is " << props.Mass()
         << " (its faces point inwards or it is empty)";
      ss.model->warnings.push_back(os.str());
    }
  } catch (const Standard_Failure& e) {
    ss.model->warnings.push_back(label + ": OpenCASCADE's shape check failed (" + failure_text(e) +
                                 ")");
  }
}

// Splits a part into bodies: one per solid, one per free shell, one for the remaining faces.
void emit_part(const TopoDS_Shape& part, const Rigid_pose_3& placement, const std::string& name,
               Session& ss) {
  std::vector<TopoDS_Shape> pieces;
  for (TopExp_Explorer x(part, TopAbs_SOLID); x.More(); x.Next()) pieces.push_back(x.Current());
  for (TopExp_Explorer x(part, TopAbs_SHELL, TopAbs_SOLID); x.More(); x.Next())
    pieces.push_back(x.Current());
  {
    TopoDS_Compound loose;
    BRep_Builder bb;
    bb.MakeCompound(loose);
    bool any = false;
    for (TopExp_Explorer x(part, TopAbs_FACE, TopAbs_SHELL); x.More(); x.Next()) {
      bb.Add(loose, x.Current());
      any = true;
    }
    if (any) pieces.push_back(loose);
  }
  int edges_alone = 0;
  for (TopExp_Explorer x(part, TopAbs_EDGE, TopAbs_FACE); x.More(); x.Next()) ++edges_alone;
  if (edges_alone > 0)
    ss.skip(name + ": " + std::to_string(edges_alone) + " free edges (wireframe)",
            "curves without faces are not bodies", "skipped");

  for (std::size_t k = 0; k < pieces.size(); ++k) {
    const std::string label =
        pieces.size() == 1 ? "'" + name + "'" : "'" + name + "' solid " + std::to_string(k + 1);
    // A solid, or a shell (OpenCASCADE's healing turns a solid whose shell is open into one).
    if (pieces[k].ShapeType() == TopAbs_SOLID || pieces[k].ShapeType() == TopAbs_SHELL)
      check_solid(pieces[k], label, ss);
    Body b = convert_shape(pieces[k], ss, label);
    if (b.faces.empty()) {
      ss.skip(label, "no face could be converted", "body skipped");
      continue;
    }
    b.source_name = name;
    b.placement = placement;
    ss.model->bodies.push_back(std::move(b));
  }
}

// Walks the XCAF assembly tree: placements compose down the tree, names come from instances
// (components) or, failing that, from the parts.
void visit_label(const Handle(XCAFDoc_ShapeTool)& st, const TDF_Label& label,
                 const TopLoc_Location& loc, const std::string& name, Session& ss, int depth) {
  if (depth > 64) {
    ss.skip(name, "assembly nesting deeper than 64 levels (a cycle?)", "skipped");
    return;
  }
  if (XCAFDoc_ShapeTool::IsAssembly(label)) {
    TDF_LabelSequence comps;
    XCAFDoc_ShapeTool::GetComponents(label, comps, Standard_False);
    for (int i = 1; i <= comps.Length(); ++i) {
      const TDF_Label c = comps.Value(i);
      TDF_Label ref;
      if (!XCAFDoc_ShapeTool::GetReferredShape(c, ref)) continue;
      std::string n = label_name(c);
      if (n.empty()) n = label_name(ref);
      visit_label(st, ref, loc * XCAFDoc_ShapeTool::GetLocation(c), n.empty() ? name : n, ss,
                  depth + 1);
    }
    return;
  }
  TopoDS_Shape shape = XCAFDoc_ShapeTool::GetShape(label);
  if (shape.IsNull()) return;
  const TopLoc_Location total = loc * shape.Location();
  if (std::abs(std::abs(total.Transformation().ScaleFactor()) - 1.0) > 1e-9)
    ss.model->warnings.push_back("'" + name + "': placement has a scale factor; it is ignored");
  shape.Location(TopLoc_Location());
  emit_part(shape, to_pose(total, ss.scale), name, ss);
}

std::string unit_from_step(STEPControl_Reader& r) {
  TColStd_SequenceOfAsciiString len, ang, solid;
  try {
    r.FileUnits(len, ang, solid);
  } catch (const Standard_Failure&) {
    return {};
  }
  if (len.Length() == 0) return {};
  std::string u = len.Value(1).ToCString();
  for (int i = 2; i <= len.Length(); ++i)
    if (u != len.Value(i).ToCString()) u += "(+others)";
  return u;
}

std::string unit_from_iges(IGESControl_Reader& r) {
  Handle(IGESData_IGESModel) m = r.IGESModel();
  if (m.IsNull()) return {};
  Handle(TCollection_HAsciiString) n = m->GlobalSection().UnitName();
  std::string s = n.IsNull() ? std::string() : n->ToCString();
  // Global section unit names are like "MM", "INCH", "2HMM" already stripped.
  return s;
}

// Entities OpenCASCADE failed to transfer, with the scan's reason where it has one (the scan
// reads the entity as the file writes it; OpenCASCADE's messages are often generic, e.g.
// "Surface has not been created"). Problems the scan found in entities that OpenCASCADE
// transferred all the same become warnings.
void report_transfer_failures(Session& ss) {
  std::map<std::string, std::string> unused = ss.scan ? ss.scan->entity_problems
                                                      : std::map<std::string, std::string>();
  if (!ss.ws.IsNull()) {
    try {
      Handle(XSControl_TransferReader) tr = ss.ws->TransferReader();
      if (!tr.IsNull() && !tr->TransientProcess().IsNull()) {
        Interface_CheckIterator checks = tr->TransientProcess()->CheckList(Standard_False);
        int reported = 0;
        for (checks.Start(); checks.More(); checks.Next()) {
          const Handle(Interface_Check)& ch = checks.Value();
          if (ch.IsNull() || !ch->HasFailed()) continue;
          std::string ent;
          std::string label;
          if (!ch->Entity().IsNull()) {
            label = ss.file_label(ch->Entity());
            ent = ss.entity_text(ch->Entity());
          } else {
            ent = ss.format_word + " entity " + std::to_string(checks.Number());
          }
          std::string reason;
          for (int i = 1; i <= ch->NbFails(); ++i) {
            std::string fail = ch->CFail(i);
            fail.erase(0, fail.find_first_not_of(' '));
            reason += (i > 1 ? "; " : "") + fail;
          }
          const auto known = unused.find(label);
          if (known != unused.end()) {
            reason = known->second + (reason.empty() ? "" : " (OpenCASCADE: " + reason + ")");
            unused.erase(known);
          }
          if (++reported > 200) {
            ss.model->warnings.push_back("more transfer failures not listed");
            break;
          }
          ss.skip(ent, reason, "not transferred by OpenCASCADE");
        }
      }
    } catch (const Standard_Failure&) {
    }
  }
  for (const auto& [label, problem] : unused)
    ss.model->warnings.push_back(ss.format_word + (ss.format_word == "IGES" ? " entity " : " ") +
                                 label + ": " + problem + " (OpenCASCADE read it all the same)");
}

// " (STEP #20: reason; ...)": the scan's problems with single entities, the first three, for a
// file OpenCASCADE transfers nothing of (it often says nothing about why). Empty when none.
std::string scan_reasons(const Session& ss) {
  if (!ss.scan || ss.scan->entity_problems.empty()) return {};
  std::string out = " (";
  std::size_t shown = 0;
  for (const auto& [label, problem] : ss.scan->entity_problems) {
    if (shown == 3) {
      out += "; and " + std::to_string(ss.scan->entity_problems.size() - 3) + " more";
      break;
    }
    out += (shown++ ? "; " : "") + ss.format_word +
           (ss.format_word == "IGES" ? " entity " : " ") + label + ": " + problem;
  }
  return out + ")";
}

std::string stem(const std::string& path) {
  std::string s = path.substr(path.find_last_of("/\\") + 1);
  const auto dot = s.find_last_of('.');
  return dot == std::string::npos || dot == 0 ? s : s.substr(0, dot);
}

}  // namespace

void read_occt(const std::string& path, Model_format format, const Read_options& options,
               const Cad_scan& scan, Model& model) {
  std::lock_guard<std::mutex> lock(occt_mutex());
  quiet_occt();
  Session ss;
  ss.path = path;
  ss.options = &options;
  ss.scan = &scan;
  ss.model = &model;
  try {
    // OpenCASCADE converts lengths to millimetres; we scale millimetres to the scene unit.
    Interface_Static::SetCVal("xstep.cascade.unit", "MM");
    if (format == Model_format::Brep) {
      ss.format_word = "BREP";
      TopoDS_Shape shape;
      BRep_Builder bb;
      if (!BRepTools::Read(shape, path.c_str(), bb) || shape.IsNull())
        throw Invalid_input(path + ": not a readable OpenCASCADE BREP file");
      model.format_name = "OpenCASCADE BREP";
      model.file_unit = options.unitless_file_unit + " (assumed: BREP files carry no unit)";
      ss.scale = scene_scale(options.unitless_file_unit, options);
      model.scale_to_unit = ss.scale;
      const std::string name = stem(path);
      const TopLoc_Location loc = shape.Location();
      shape.Location(TopLoc_Location());
      emit_part(shape, to_pose(loc, ss.scale), name, ss);
      return;
    }

    Handle(TDocStd_Document) doc;
    Handle(XCAFApp_Application) app = XCAFApp_Application::GetApplication();
    app->NewDocument("MDTV-XCAF", doc);
    struct Closer {
      Handle(XCAFApp_Application) app;
      Handle(TDocStd_Document) doc;
      ~Closer() {
        try {
          if (!doc.IsNull() && app->CanClose(doc) == CDM_CCS_OK) app->Close(doc);
        } catch (...) {
        }
      }
    } closer{app, doc};

    if (format == Model_format::Step) {
      ss.format_word = "STEP";
      STEPCAFControl_Reader reader;
      reader.SetNameMode(true);
      reader.SetColorMode(false);
      reader.SetLayerMode(false);
      reader.SetPropsMode(false);
      const IFSelect_ReturnStatus st = reader.ReadFile(path.c_str());
      if (st != IFSelect_RetDone)
        throw Invalid_input(path + ": not a readable STEP file (OpenCASCADE reader status " +
                            std::to_string(static_cast<int>(st)) + ")" + scan_reasons(ss));
      ss.ws = reader.Reader().WS();
      const std::string unit = unit_from_step(reader.ChangeReader());
      model.file_unit = unit.empty() ? "mm (no unit declared)" : unit;
      {
        std::string schema;
        Handle(Interface_InterfaceModel) m = ss.ws->Model();
        // The header's FILE_SCHEMA names the application protocol.
        std::ifstream in(path);
        std::string line, head;
        for (int i = 0; i < 40 && std::getline(in, line); ++i) head += line;
        if (head.find("AP242") != std::string::npos || head.find("242") != std::string::npos)
          schema = "AP242";
        else if (head.find("AUTOMOTIVE_DESIGN") != std::string::npos)
          schema = "AP214";
        else if (head.find("CONFIG_CONTROL_DESIGN") != std::string::npos)
          schema = "AP203";
        model.format_name = schema.empty() ? "STEP" : "STEP " + schema;
      }
      if (!reader.Transfer(doc))
        throw Invalid_input(path + ": STEP file has no shape OpenCASCADE can transfer" +
                            scan_reasons(ss));
    } else {
      ss.format_word = "IGES";
      IGESCAFControl_Reader reader;
      reader.SetNameMode(true);
      reader.SetColorMode(false);
      reader.SetLayerMode(false);
      const IFSelect_ReturnStatus st = reader.ReadFile(path.c_str());
      if (st != IFSelect_RetDone)
        throw Invalid_input(path + ": not a readable IGES file (OpenCASCADE reader status " +
                            std::to_string(static_cast<int>(st)) + ")" + scan_reasons(ss));
      ss.ws = reader.WS();
      const std::string unit = unit_from_iges(reader);
      model.file_unit = unit.empty() ? "mm (no unit declared)" : unit;
      model.format_name = "IGES";
      if (!reader.Transfer(doc))
        throw Invalid_input(path + ": IGES file has no entity OpenCASCADE can transfer" +
                            scan_reasons(ss));
    }
    ss.scale = scene_scale("mm", options);
    model.scale_to_unit = ss.scale;
    report_transfer_failures(ss);

    Handle(XCAFDoc_ShapeTool) st = XCAFDoc_DocumentTool::ShapeTool(doc->Main());
    TDF_LabelSequence roots;
    st->GetFreeShapes(roots);
    const std::string fallback = stem(path);
    for (int i = 1; i <= roots.Length(); ++i) {
      std::string n = label_name(roots.Value(i));
      visit_label(st, roots.Value(i), TopLoc_Location(), n.empty() ? fallback : n, ss, 0);
    }
  } catch (const Standard_OutOfMemory&) {
    throw std::bad_alloc();
  } catch (const Standard_Failure& e) {
    throw Invalid_input(path + ": OpenCASCADE failed while reading (" + failure_text(e) + ")");
  }
}

}  // namespace extremal::io::internal
