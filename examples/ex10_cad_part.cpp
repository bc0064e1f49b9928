//                         sage example 10: a CAD part, its faces as boundary parts
//
// Sample runs:  ex10_cad_part bracket.step
//
// Description:  Builds an aluminium L-bracket with OpenCASCADE (a base plate
//               and an upright, filleted where they meet, two bolt holes in
//               the base and a load hole in the upright; millimetres),
//               writes it as a STEP file and reads it back as `sage info`
//               and problem files read CAD files. Checks what sage read
//               against OCCT's own answers: the face count, every face's
//               area (BRepGProp), the holes found by face queries, and the
//               volume the tessellation encloses (within the deflection
//               times the area). Exits 1 if a check fails.
//               The bundled examples/models/bracket.step, which
//               examples/problems/cad_bracket_heat.json and
//               cad_bracket_stress.json solve on, is this program's output.
//               Adds to example 7: CAD files, faces, OCCT.

#include <sage/geometry/cad_model.hpp>
#include <sage/geometry/model.hpp>

#include <BRepAlgoAPI_Cut.hxx>
#include <BRepAlgoAPI_Fuse.hxx>
#include <BRepFilletAPI_MakeFillet.hxx>
#include <BRepGProp.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <BRep_Tool.hxx>
#include <GProp_GProps.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <Message_PrinterOStream.hxx>
#include <STEPControl_Writer.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Vertex.hxx>

#include <cmath>
#include <cstdio>
#include <exception>
#include <string>

namespace {

bool near(double a, double b, double tolerance) { return std::abs(a - b) <= tolerance; }

/// The straight edge where the base's top (z = 8) meets the upright's
/// inner face (x = 8): the one to fillet.
TopoDS_Edge inner_corner(const TopoDS_Shape& shape) {
  for (TopExp_Explorer e(shape, TopAbs_EDGE); e.More(); e.Next()) {
    const TopoDS_Edge edge = TopoDS::Edge(e.Current());
    const gp_Pnt a = BRep_Tool::Pnt(TopExp::FirstVertex(edge)), b = BRep_Tool::Pnt(TopExp::LastVertex(edge));
    if (near(a.X(), 8, 1e-9) && near(b.X(), 8, 1e-9) && near(a.Z(), 8, 1e-9) && near(b.Z(), 8, 1e-9)) return edge;
  }
  throw std::runtime_error("no inner corner edge");
}

/// The bracket, in millimetres: base 80 x 40 x 8, upright 8 x 40 x 60,
/// fillet radius 6 where they meet; bolt holes of radius 4 through the
/// base at x = 45 and 68, a load hole of radius 6 through the upright.
TopoDS_Shape bracket() {
  const TopoDS_Shape base = BRepPrimAPI_MakeBox(gp_Pnt(0, 0, 0), 80, 40, 8).Shape();
  const TopoDS_Shape upright = BRepPrimAPI_MakeBox(gp_Pnt(0, 0, 8), 8, 40, 52).Shape();
  const TopoDS_Shape l = BRepAlgoAPI_Fuse(base, upright).Shape();
  BRepFilletAPI_MakeFillet fillet(l);
  fillet.Add(6.0, inner_corner(l));
  TopoDS_Shape part = fillet.Shape();
  for (const double x : {45.0, 68.0})
    part = BRepAlgoAPI_Cut(part, BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(x, 20, -1), gp_Dir(0, 0, 1)), 4, 10).Shape())
               .Shape();
  return BRepAlgoAPI_Cut(part, BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(-1, 20, 40), gp_Dir(1, 0, 0)), 6, 10).Shape())
      .Shape();
}

int failures = 0;
void check(bool ok, const std::string& what) {
  std::printf("  %-62s %s\n", what.c_str(), ok ? "ok" : "FAILED");
  failures += ok ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) try {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s OUT.step\n", argv[0]);
    return 2;
  }
  // OCCT's writer prints transfer statistics: not wanted here.
  Message::DefaultMessenger()->RemovePrinters(STANDARD_TYPE(Message_PrinterOStream));
  const TopoDS_Shape part = bracket();
  STEPControl_Writer writer;
  if (writer.Transfer(part, STEPControl_AsIs) != IFSelect_RetDone || writer.Write(argv[1]) != IFSelect_RetDone)
    throw std::runtime_error(std::string("cannot write ") + argv[1]);

  const sage::geometry::Model model = sage::geometry::load_model(argv[1]);
  std::printf("%s: %zu faces, %zu triangles, in %s\n", argv[1], model.faces.size(), model.surface->triangles.size(),
              model.unit.c_str());
  for (std::size_t f = 1; f <= model.faces.size(); ++f)
    std::printf("  %s\n", sage::geometry::describe_face(model, f).c_str());

  int faces = 0;
  double area = 0;
  bool areas_agree = true;
  for (TopExp_Explorer e(part, TopAbs_FACE); e.More(); e.Next(), ++faces) {
    GProp_GProps face;
    BRepGProp::SurfaceProperties(e.Current(), face);
    area += face.Mass();
    areas_agree = areas_agree && near(model.faces.at(static_cast<std::size_t>(faces)).area, face.Mass(), 1e-9);
  }
  check(static_cast<int>(model.faces.size()) == faces, "as many faces as OCCT counts");
  check(areas_agree, "each face's area as BRepGProp gives it");
  check(sage::geometry::faces_matching(model, "cylinder radius 4").size() == 2, "two bolt holes (cylinder radius 4)");
  check(sage::geometry::faces_matching(model, "cylinder radius 6 axis 1 0 0").size() == 1,
        "one load hole (cylinder radius 6 axis 1 0 0)");
  check(sage::geometry::faces_matching(model, "cylinder radius 6 axis 0 1 0").size() == 1,
        "the fillet (cylinder radius 6 axis 0 1 0)");

  // The volume the triangles enclose (divergence theorem) against OCCT's.
  double volume = 0;
  for (const auto& t : model.surface->triangles) {
    const auto &a = model.surface->points[t[0]], &b = model.surface->points[t[1]], &c = model.surface->points[t[2]];
    volume +=
        (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0])) /
        6;
  }
  GProp_GProps solid;
  BRepGProp::VolumeProperties(part, solid);
  const double deflection = 1e-3 * std::sqrt(80.0 * 80 + 40 * 40 + 60 * 60);
  std::printf("  volume: %.6g mm^3 from the triangles, %.6g from OCCT\n", volume, solid.Mass());
  check(std::abs(volume - solid.Mass()) <= deflection * area, "volume within deflection x area of OCCT's");
  return failures ? 1 : 0;
} catch (const std::exception& e) {
  std::fprintf(stderr, "ex10_cad_part: %s\n", e.what());
  return 1;
}
