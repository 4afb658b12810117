// Import time of STEP files against OpenCASCADE's own read of the same file, in the same run
// (bench/RESULTS.md, "Import"). For each file, medians of `--repeat` runs (default 3) of:
//   occt_read     STEPControl_Reader ReadFile + TransferRoots (OpenCASCADE's plain read)
//   occt_check    BRepCheck_Analyzer of every solid (or of the whole shape if it has none)
//   occt_convert  BRepBuilderAPI_NurbsConvert of the same pieces
//                 (the last two: OpenCASCADE work our reader adds on top of the read)
//   extremal      io::read_model (what `extremal info FILE` spends reading)
// Usage: bench_import [--repeat N] FILE...
// CGAL (through our headers) before OpenCASCADE: OpenCASCADE's Handle macro breaks CGAL.
#include "io/Model_reader.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <string>
#include <vector>

#include <BRepBuilderAPI_NurbsConvert.hxx>
#include <BRepCheck_Analyzer.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <Message_PrinterOStream.hxx>
#include <STEPControl_Reader.hxx>
#include <TopExp_Explorer.hxx>
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

TopoDS_Shape occt_read(const char* path) {
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
    else
      files.push_back(argv[i]);
  }
  if (files.empty()) {
    std::fprintf(stderr, "usage: bench_import [--repeat N] FILE...\n");
    return 2;
  }
  std::printf("%-28s %6s %11s %12s %14s %12s %7s\n", "file", "faces", "occt_read_s",
              "occt_check_s", "occt_convert_s", "extremal_s", "ratio");
  for (const std::string& f : files) {
    std::vector<double> t_read, t_check, t_conv, t_ours;
    int faces = 0;
    for (int k = 0; k < repeat; ++k) {
      TopoDS_Shape shape;
      t_read.push_back(seconds([&] { shape = occt_read(f.c_str()); }));
      t_check.push_back(seconds([&] { occt_check(shape); }));
      t_conv.push_back(seconds([&] { occt_convert(shape); }));
      extremal::io::Model m;
      t_ours.push_back(seconds([&] { m = extremal::io::read_model(f); }));
      faces = 0;
      for (const auto& b : m.bodies) faces += static_cast<int>(b.faces.size());
    }
    const double r = median(t_read), k = median(t_check), c = median(t_conv), o = median(t_ours);
    const std::string name = f.substr(f.find_last_of('/') + 1);
    std::printf("%-28s %6d %11.3f %12.3f %14.3f %12.3f %7.2f\n", name.c_str(), faces, r, k, c, o,
                o / r);
  }
  return 0;
}
