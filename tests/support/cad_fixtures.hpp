#pragma once
// CAD files for the tests, made with OpenCASCADE itself: solids built from
// primitives and Booleans, written as STEP (in a chosen unit), IGES or BREP.

#include <sage/expression/expression.hpp>
#include <sage/tape/evaluator.hpp>
#include <sage/tape/tape.hpp>

#include <BRepAlgoAPI_Cut.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <BRepPrimAPI_MakeSphere.hxx>
#include <BRepPrimAPI_MakeTorus.hxx>
#include <BRepTools.hxx>
#include <IGESControl_Controller.hxx>
#include <IGESControl_Writer.hxx>
#include <Interface_Static.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <Message_PrinterOStream.hxx>
#include <Quantity_Color.hxx>
#include <STEPCAFControl_Writer.hxx>
#include <STEPControl_Controller.hxx>
#include <STEPControl_Writer.hxx>
#include <StepData_StepModel.hxx>
#include <StepShape_AdvancedFace.hxx>
#include <StepShape_ManifoldSolidBrep.hxx>
#include <TCollection_HAsciiString.hxx>
#include <TDocStd_Document.hxx>
#include <TopExp.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS_Shape.hxx>
#include <TransferBRep.hxx>
#include <TransferBRep_ShapeMapper.hxx>
#include <Transfer_FinderProcess.hxx>
#include <XCAFApp_Application.hxx>
#include <XCAFDoc_ColorTool.hxx>
#include <XCAFDoc_DocumentTool.hxx>
#include <XCAFDoc_ShapeTool.hxx>
#include <XSControl_TransferWriter.hxx>
#include <XSControl_WorkSession.hxx>

#include <array>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace sage::test {

/// The point of the zero set of a normalized field nearest p (Newton
/// steps): a point of an exact CAD face from one near it.
inline std::array<double, 3> onto_surface(const Expr& surface, std::array<double, 3> p) {
  const Tape tape(surface, 3);
  Evaluator<Tuple<3, 1>> eval(tape);
  for (int step = 0; step < 20; ++step) {
    const Tuple<3, 1> t = eval.at(p);
    const auto g = t.gradient();
    const double g2 = g[0] * g[0] + g[1] * g[1] + g[2] * g[2];
    for (int a = 0; a < 3; ++a) p[a] -= t.value() * g[a] / g2;
  }
  return p;
}

/// OCCT's writers print transfer statistics to stdout: silenced once.
inline void quiet_occt() {
  static std::once_flag once;
  std::call_once(once, [] { Message::DefaultMessenger()->RemovePrinters(STANDARD_TYPE(Message_PrinterOStream)); });
}

/// The block [-1, 1] x [-1, 1] x [0, 1] with a vertical channel of radius
/// 0.4 through it (the CSG model of examples/problems/block_with_hole.json).
/// The cylinder's seam is turned off the axes, so that the tessellation's
/// nodes do not sit on round coordinates.
inline TopoDS_Shape block_with_channel() {
  const TopoDS_Shape box = BRepPrimAPI_MakeBox(gp_Pnt(-1, -1, 0), 2, 2, 1).Shape();
  const TopoDS_Shape channel =
      BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(0, 0, -1), gp_Dir(0, 0, 1), gp_Dir(0.8, 0.6, 0)), 0.4, 3).Shape();
  return BRepAlgoAPI_Cut(box, channel).Shape();
}

/// `shape` written through an XCAF document with colours: the whole shape's
/// (`solid`, unless empty) and faces' own (`faces`: face number from 1, as
/// TopExp::MapShapes counts them, and its RGB in 0..1).
inline void write_coloured_step(const TopoDS_Shape& shape, const std::string& path,
                                const std::optional<std::array<double, 3>>& solid,
                                const std::vector<std::pair<int, std::array<double, 3>>>& faces) {
  quiet_occt();
  Handle(TDocStd_Document) doc;
  XCAFApp_Application::GetApplication()->NewDocument("MDTV-XCAF", doc);
  const Handle(XCAFDoc_ShapeTool) shapes = XCAFDoc_DocumentTool::ShapeTool(doc->Main());
  const Handle(XCAFDoc_ColorTool) colours = XCAFDoc_DocumentTool::ColorTool(doc->Main());
  const TDF_Label label = shapes->AddShape(shape, false);
  const auto rgb = [](const std::array<double, 3>& c) { return Quantity_Color(c[0], c[1], c[2], Quantity_TOC_RGB); };
  if (solid) colours->SetColor(label, rgb(*solid), XCAFDoc_ColorSurf);
  TopTools_IndexedMapOfShape map;
  TopExp::MapShapes(shape, TopAbs_FACE, map);
  for (const auto& [face, colour] : faces) {
    const TDF_Label sub = shapes->AddSubShape(label, map(face));
    if (sub.IsNull()) throw std::runtime_error("face " + std::to_string(face) + " is not a sub-shape");
    colours->SetColor(sub, rgb(colour), XCAFDoc_ColorSurf);
  }
  STEPCAFControl_Writer writer;
  writer.SetColorMode(true);
  if (!writer.Transfer(doc, STEPControl_AsIs) || writer.Write(path.c_str()) != IFSelect_RetDone)
    throw std::runtime_error("cannot write " + path);
}

/// `unit` as OCCT's STEP writer names it: "MM", "M", "INCH", "FT", ...;
/// `face_names`: the ADVANCED_FACE names of faces 1, 2, ... (TopExp::MapShapes'
/// numbering; empty strings leave a face unnamed).
inline void write_step(const TopoDS_Shape& shape, const std::string& path, const char* unit = "MM",
                       STEPControl_StepModelType mode = STEPControl_AsIs,
                       const std::vector<std::string>& face_names = {},
                       const std::vector<std::string>& solid_names = {}) {
  quiet_occt();
  static std::mutex m;  // the unit is a process-wide parameter
  std::lock_guard<std::mutex> lock(m);
  STEPControl_Controller::Init();  // declares the parameters set below
  if (!Interface_Static::SetCVal("write.step.unit", unit)) throw std::runtime_error(std::string("unit ") + unit);
  STEPControl_Writer writer;
  if (writer.Transfer(shape, mode) != IFSelect_RetDone) throw std::runtime_error("cannot transfer " + path);
  const Handle(Transfer_FinderProcess) process = writer.WS()->TransferWriter()->FinderProcess();
  TopTools_IndexedMapOfShape faces;
  TopExp::MapShapes(shape, TopAbs_FACE, faces);
  for (std::size_t f = 0; f < face_names.size() && static_cast<int>(f) < faces.Extent(); ++f) {
    if (face_names[f].empty()) continue;
    const Handle(StepShape_AdvancedFace) entity = Handle(StepShape_AdvancedFace)::DownCast(
        process->FindTransient(TransferBRep::ShapeMapper(process, faces(static_cast<int>(f) + 1))));
    if (entity.IsNull()) throw std::runtime_error("no STEP face for face " + std::to_string(f + 1));
    entity->SetName(new TCollection_HAsciiString(face_names[f].c_str()));
  }
  // Solids' names, in the order their MANIFOLD_SOLID_BREP entities were written.
  std::size_t named = 0;
  for (int i = 1; i <= writer.Model()->NbEntities() && named < solid_names.size(); ++i)
    if (const Handle(StepShape_ManifoldSolidBrep) solid =
            Handle(StepShape_ManifoldSolidBrep)::DownCast(writer.Model()->Value(i));
        !solid.IsNull())
      solid->SetName(new TCollection_HAsciiString(solid_names[named++].c_str()));
  if (named < solid_names.size()) throw std::runtime_error("fewer STEP solids than solid names");
  if (writer.Write(path.c_str()) != IFSelect_RetDone) throw std::runtime_error("cannot write " + path);
  Interface_Static::SetCVal("write.step.unit", "MM");
}

inline void write_iges(const TopoDS_Shape& shape, const std::string& path) {
  quiet_occt();
  IGESControl_Controller::Init();
  IGESControl_Writer writer("MM", 1);  // 1: solids as B-rep entities (MSBO)
  writer.AddShape(shape);
  writer.ComputeModel();
  if (!writer.Write(path.c_str())) throw std::runtime_error("cannot write " + path);
}

inline void write_brep(const TopoDS_Shape& shape, const std::string& path) {
  if (!BRepTools::Write(shape, path.c_str())) throw std::runtime_error("cannot write " + path);
}

}  // namespace sage::test
