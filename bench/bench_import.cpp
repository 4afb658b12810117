// Import time of STEP files against OpenCASCADE's own read of the same file, in the same run
// (bench/RESULTS.md, "Import"). For each file, medians of `--repeat` runs (default 3) of:
//   occt_read     STEPControl_Reader ReadFile + TransferRoots (OpenCASCADE's plain read)
//   occt_check    BRepCheck_Analyzer of every solid (or of the whole shape if it has none)
//   occt_convert  BRepBuilderAPI_NurbsConvert of the same pieces
//                 (the last two: OpenCASCADE work our reader adds on top of the read)
//   extremal      io::read_model (what `extremal info FILE` spends reading: OpenCASCADE in a
//                 child process, docs/import.md "Limits and containment")
//   in_process    io::read_model with Import_limits::isolate off (OpenCASCADE in this process)
// For .brep files the OpenCASCADE read is BRepTools::Read. `--write-offset-faces DIR` first writes
// two faces on offset surfaces there (offset_bspline.brep: a bicubic patch offset by 2 mm, which
// OpenCASCADE approximates keeping its parameters; offset_cylinder.brep: a cylinder offset by
// 1.5 mm, converted to a rational cylinder with other parameters): the deviation measurement of
// approximated faces (Face::approximation_error) was most of their import time.
// Usage: bench_import [--repeat N] [--write-offset-faces DIR] FILE...
// CGAL (through our headers) before OpenCASCADE: OpenCASCADE's Handle macro breaks CGAL.
#include "io/Model_reader.h"

#include <algorithm>
#include <cmath>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <string>
#include <vector>

#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_NurbsConvert.hxx>
#include <BRepTools.hxx>
#include <BRep_Builder.hxx>
#include <Geom_BSplineSurface.hxx>
#include <Geom_CylindricalSurface.hxx>
#include <Geom_OffsetSurface.hxx>
#include <BRepCheck_Analyzer.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <Message_PrinterOStream.hxx>
#include <STEPControl_Reader.hxx>
#include <TColStd_Array1OfInteger.hxx>
#include <TColStd_Array1OfReal.hxx>
#include <TColgp_Array2OfPnt.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS_Face.hxx>
#include <gp_Ax3.hxx>
#include <TopoDS_Shape.hxx>

namespace {

double seconds(const std::function<void()>& f) {
  const auto t0 = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

bool is_brep(const std::string& path) {
  return path.size() > 5 && path.compare(path.size() - 5, 5, ".brep") == 0;
}

void write_offset_faces(const std::string& dir) {
  TColgp_Array2OfPnt p(1, 4, 1, 4);
  for (int i = 1; i <= 4; ++i)
    for (int j = 1; j <= 4; ++j) p(i, j) = gp_Pnt(10.0 * i, 10.0 * j, 3.0 * std::sin(i + 0.7 * j));
  TColStd_Array1OfReal k(1, 2);
  k(1) = 0.0;
  k(2) = 1.0;
  TColStd_Array1OfInteger m(1, 2);
  m(1) = m(2) = 4;
  Handle(Geom_BSplineSurface) b = new Geom_BSplineSurface(p, k, k, m, m, 3, 3);
  BRepTools::Write(
      BRepBuilderAPI_MakeFace(new Geom_OffsetSurface(b, 2.0), 0.0, 1.0, 0.0, 1.0, 1e-7).Face(),
      (dir + "/offset_bspline.brep").c_str());
  Handle(Geom_OffsetSurface) c =
      new Geom_OffsetSurface(new Geom_CylindricalSurface(gp_Ax3(), 5.0), 1.5);
  BRepTools::Write(BRepBuilderAPI_MakeFace(c, 0.2, 2.0, -3.0, 4.0, 1e-7).Face(),
                   (dir + "/offset_cylinder.brep").c_str());
}

TopoDS_Shape occt_read(const char* path) {
  if (is_brep(path)) {
    TopoDS_Shape s;
    BRep_Builder bb;
    if (!BRepTools::Read(s, path, bb)) {
      std::fprintf(stderr, "%s: OpenCASCADE cannot read it\n", path);
      std::exit(1);
    }
    return s;
  }
  STEPControl_Reader r;
  if (r.ReadFile(path) != IFSelect_RetDone) {
    std::fprintf(stderr, "%s: OpenCASCADE cannot read it\n", path);
    std::exit(1);
  }
  r.TransferRoots();
  return r.OneShape();
}

// The pieces our reader converts: solids, or the whole shape when it has none.
std::vector<TopoDS_Shape> pieces(const TopoDS_Shape& shape) {
  std::vector<TopoDS_Shape> p;
  for (TopExp_Explorer x(shape, TopAbs_SOLID); x.More(); x.Next()) p.push_back(x.Current());
  if (p.empty()) p.push_back(shape);
  return p;
}

void occt_check(const TopoDS_Shape& shape) {
  for (const TopoDS_Shape& s : pieces(shape)) {
    BRepCheck_Analyzer check(s);
    (void)check.IsValid();
  }
}

void occt_convert(const TopoDS_Shape& shape) {
  for (const TopoDS_Shape& s : pieces(shape)) BRepBuilderAPI_NurbsConvert conv(s, Standard_True);
}

}  // namespace

int main(int argc, char** argv) {
  Message::DefaultMessenger()->RemovePrinters(STANDARD_TYPE(Message_PrinterOStream));
  int repeat = 3;
  std::vector<std::string> files;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--repeat") && i + 1 < argc)
      repeat = std::max(1, std::atoi(argv[++i]));
    else if (!std::strcmp(argv[i], "--write-offset-faces") && i + 1 < argc)
      write_offset_faces(argv[++i]);
    else
      files.push_back(argv[i]);
  }
  if (files.empty()) {
    std::fprintf(stderr, "usage: bench_import [--repeat N] [--write-offset-faces DIR] FILE...\n");
    return 2;
  }
  std::printf("%-28s %6s %11s %12s %14s %12s %7s %13s\n", "file", "faces", "occt_read_s",
              "occt_check_s", "occt_convert_s", "extremal_s", "ratio", "in_process_s");
  extremal::io::Read_options in_process;
  in_process.limits.isolate = false;
  for (const std::string& f : files) {
    std::vector<double> t_read, t_check, t_conv, t_ours, t_in;
    int faces = 0;
    for (int k = 0; k < repeat; ++k) {
      TopoDS_Shape shape;
      t_read.push_back(seconds([&] { shape = occt_read(f.c_str()); }));
      t_check.push_back(seconds([&] { occt_check(shape); }));
      t_conv.push_back(seconds([&] { occt_convert(shape); }));
      extremal::io::Model m;
      t_ours.push_back(seconds([&] { m = extremal::io::read_model(f); }));
      t_in.push_back(seconds([&] { m = extremal::io::read_model(f, in_process); }));
      faces = 0;
      for (const auto& b : m.bodies) faces += static_cast<int>(b.faces.size());
    }
    const double r = median(t_read), k = median(t_check), c = median(t_conv), o = median(t_ours);
    const std::string name = f.substr(f.find_last_of('/') + 1);
    std::printf("%-28s %6d %11.3f %12.3f %14.3f %12.3f %7.2f %13.3f\n", name.c_str(), faces, r, k,
                c, o, o / r, median(t_in));
  }
  return 0;
}
