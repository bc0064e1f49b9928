// read_cad_solid: a CAD file through OpenCASCADE's readers (STEP, IGES,
// BREP) into one checked solid. OCCT's data exchange works in millimetres
// (the "xstep.cascade.unit" default); the file's own unit is read back so
// that the model keeps the coordinates the user's CAD system shows.
#include "cad_internal.hpp"

#include <BRepAlgoAPI_Fuse.hxx>
#include <BRepBndLib.hxx>
#include <BRepBuilderAPI_MakeSolid.hxx>
#include <BRepBuilderAPI_Sewing.hxx>
#include <BRepCheck_Analyzer.hxx>
#include <BRepTools.hxx>
#include <BRep_Builder.hxx>
#include <Bnd_Box.hxx>
#include <IGESControl_Reader.hxx>
#include <IGESData_GlobalSection.hxx>
#include <IGESData_IGESModel.hxx>
#include <Interface_Static.hxx>
#include <Quantity_Color.hxx>
#include <STEPConstruct_Styles.hxx>
#include <STEPControl_Reader.hxx>
#include <ShapeFix_Shape.hxx>
#include <ShapeFix_Solid.hxx>
#include <Standard_Failure.hxx>
#include <StepData_StepModel.hxx>
#include <StepRepr_RepresentationItem.hxx>
#include <StepShape_ManifoldSolidBrep.hxx>
#include <StepVisual_Colour.hxx>
#include <StepVisual_StyledItem.hxx>
#include <TColStd_SequenceOfAsciiString.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_ListOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Compound.hxx>
#include <TopoDS_Shell.hxx>
#include <TransferBRep.hxx>
#include <Transfer_TransientProcess.hxx>
#include <XSControl_TransferReader.hxx>
#include <XSControl_WorkSession.hxx>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <mutex>

namespace sage::geometry::cad {

namespace {

[[noreturn]] void fail(const std::string& path, const std::string& what) { throw ModelError(path + ": " + what); }

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

/// Millimetres per unit for the length unit names STEP and IGES files give.
std::optional<double> millimetres_per(const std::string& name) {
  static const std::vector<std::pair<std::vector<std::string>, double>> units = {
      {{"millimetre", "millimeter", "mm"}, 1.0},
      {{"metre", "meter", "m"}, 1000.0},
      {{"centimetre", "centimeter", "cm"}, 10.0},
      {{"micrometre", "micrometer", "micron", "um"}, 1e-3},
      {{"kilometre", "kilometer", "km"}, 1e6},
      {{"inch", "in"}, 25.4},
      {{"foot", "feet", "ft"}, 304.8},
      {{"mil", "mils"}, 0.0254},
      {{"microinch", "uin"}, 25.4e-6},
      {{"mile", "mi"}, 1609344.0},
      {{"decimetre", "decimeter", "dm"}, 100.0},
  };
  const std::string n = lower(name);
  for (const auto& [names, mm] : units)
    if (std::find(names.begin(), names.end(), n) != names.end()) return mm;
  return std::nullopt;
}

// OCCT's data exchange keeps its parameters in process-wide statics.
std::mutex& exchange_mutex() {
  static std::mutex m;
  return m;
}

/// A STEP representation item's name; empty when it has none.
std::string name_of(const Handle(Standard_Transient) & entity) {
  const Handle(StepRepr_RepresentationItem) item = Handle(StepRepr_RepresentationItem)::DownCast(entity);
  if (item.IsNull() || item->Name().IsNull()) return {};
  const std::string name = item->Name()->ToCString();
  return name == "NONE" ? std::string() : name;
}

std::string hex(const Quantity_Color& colour) {
  double rgb[3];
  colour.Values(rgb[0], rgb[1], rgb[2], Quantity_TOC_RGB);  // the file's values (STEPConstruct_Styles::DecodeColor)
  char text[8];
  std::snprintf(text, sizeof text, "#%02x%02x%02x", static_cast<int>(std::lround(255 * rgb[0])),
                static_cast<int>(std::lround(255 * rgb[1])), static_cast<int>(std::lround(255 * rgb[2])));
  return text;
}

/// The surface colours of STEP's styled items (what STEPCAFControl_Reader
/// reads into XCAF), given to the faces of the shapes they style: a
/// solid's or shell's first, then the faces' own, which win.
void read_step_colours(STEPControl_Reader& reader, CadSolid& out) {
  STEPConstruct_Styles styles(reader.WS());
  if (!styles.LoadStyles()) return;
  const Handle(Transfer_TransientProcess) process = reader.WS()->TransferReader()->TransientProcess();
  std::vector<std::pair<TopoDS_Shape, std::string>> on_faces;
  for (int i = 1; i <= styles.NbStyles(); ++i) {
    const Handle(StepVisual_StyledItem) style = styles.Style(i);
    Handle(StepVisual_Colour) surface, boundary, curve, render;
    Standard_Real transparency = 0;
    Standard_Boolean component = false;
    if (!styles.GetColors(style, surface, boundary, curve, render, transparency, component)) continue;
    const Handle(StepVisual_Colour)& chosen = surface.IsNull() ? render : surface;
    Quantity_Color colour;
    if (chosen.IsNull() || !STEPConstruct_Styles::DecodeColor(chosen, colour)) continue;
    const TopoDS_Shape styled = TransferBRep::ShapeResult(process, process->Find(style->ItemAP242().Value()));
    if (styled.IsNull()) continue;
    auto& into = styled.ShapeType() == TopAbs_FACE ? on_faces : out.face_colours;
    for (TopExp_Explorer e(styled, TopAbs_FACE); e.More(); e.Next()) into.emplace_back(e.Current(), hex(colour));
  }
  out.face_colours.insert(out.face_colours.end(), on_faces.begin(), on_faces.end());
}

TopoDS_Shape read_step(const std::string& path, CadSolid& out) {
  std::lock_guard<std::mutex> lock(exchange_mutex());
  STEPControl_Reader reader;
  if (reader.ReadFile(path.c_str()) != IFSelect_RetDone)
    fail(path, "not a readable STEP file (OpenCASCADE's STEP reader refused it)");
  TColStd_SequenceOfAsciiString lengths, angles, solid_angles;
  reader.FileUnits(lengths, angles, solid_angles);
  if (lengths.IsEmpty()) {
    out.unit = "millimetre";
    out.notes.push_back("unit: none declared in the file; millimetres assumed (STEP's default)");
  } else {
    out.unit = lower(lengths(1).ToCString());
    const auto mm = millimetres_per(out.unit);
    if (!mm) fail(path, "unknown length unit '" + std::string(lengths(1).ToCString()) + "'");
    out.millimetres_per_unit = *mm;
    for (int i = 2; i <= lengths.Length(); ++i)
      if (lower(lengths(i).ToCString()) != out.unit)
        out.notes.push_back("unit: the file declares several length units (" + out.unit + ", " +
                            lengths(i).ToCString() + "); coordinates are in the first, " + out.unit);
  }
  if (reader.NbRootsForTransfer() == 0) fail(path, "no shape to transfer: the STEP file holds no geometry entity");
  reader.TransferRoots();
  // Root entities that gave no shape, by STEP type (StepShape_... -> the class name).
  std::map<std::string, int> unread;
  const Handle(XSControl_TransferReader) results = reader.WS()->TransferReader();
  for (int i = 1; i <= reader.NbRootsForTransfer(); ++i) {
    const Handle(Standard_Transient) root = reader.RootForTransfer(i);
    if (!root.IsNull() && !results->HasResult(root)) ++unread[root->DynamicType()->Name()];
  }
  std::string unread_list;
  for (const auto& [type, n] : unread)
    unread_list += (unread_list.empty() ? "" : ", ") + type + (n > 1 ? " (" + std::to_string(n) + ")" : "");
  if (reader.NbShapes() == 0)
    fail(path, "no shape transferred: the STEP file's entities are not ones OpenCASCADE reads as geometry" +
                   (unread_list.empty() ? std::string() : " (" + unread_list + ")"));
  if (!unread.empty()) out.notes.push_back("entities not read (OpenCASCADE gave no shape for them): " + unread_list);
  const TopoDS_Shape shape = reader.OneShape();
  // The names of the STEP entities the faces and solids came from.
  const Handle(XSControl_TransferReader) transfer = reader.WS()->TransferReader();
  for (TopExp_Explorer e(shape, TopAbs_FACE); e.More(); e.Next())
    if (const std::string name = name_of(transfer->EntityFromShapeResult(e.Current(), 1)); !name.empty())
      out.face_names.emplace_back(e.Current(), name);
  const Handle(Transfer_TransientProcess) process = transfer->TransientProcess();
  for (int i = 1; i <= reader.Model()->NbEntities(); ++i) {
    const Handle(Standard_Transient) entity = reader.Model()->Value(i);
    if (!entity->IsKind(STANDARD_TYPE(StepShape_ManifoldSolidBrep))) continue;
    const TopoDS_Shape solid = TransferBRep::ShapeResult(process, process->Find(entity));
    if (const std::string name = name_of(entity); !solid.IsNull() && !name.empty())
      out.solid_names.emplace_back(solid, name);
  }
  read_step_colours(reader, out);
  return shape;
}

TopoDS_Shape read_iges(const std::string& path, CadSolid& out) {
  std::lock_guard<std::mutex> lock(exchange_mutex());
  IGESControl_Reader reader;
  if (reader.ReadFile(path.c_str()) != IFSelect_RetDone)
    fail(path, "not a readable IGES file (OpenCASCADE's IGES reader refused it)");
  const IGESData_GlobalSection& global = reader.IGESModel()->GlobalSection();
  const double metres = global.UnitValue();
  if (!(metres > 0)) fail(path, "unknown length unit (IGES unit flag " + std::to_string(global.UnitFlag()) + ")");
  out.millimetres_per_unit = 1000 * metres;
  out.unit = global.UnitName().IsNull() ? std::string("unit flag ") + std::to_string(global.UnitFlag())
                                        : lower(global.UnitName()->ToCString());
  if (const auto mm = millimetres_per(out.unit)) out.millimetres_per_unit = *mm;
  reader.TransferRoots();
  if (reader.NbShapes() == 0)
    fail(path, "no shape transferred: the IGES file holds no surface or solid entity OpenCASCADE reads");
  return reader.OneShape();
}

TopoDS_Shape read_brep(const std::string& path, CadSolid& out) {
  TopoDS_Shape shape;
  BRep_Builder builder;
  if (!BRepTools::Read(shape, path.c_str(), builder) || shape.IsNull())
    fail(path, "not a readable BREP file (OpenCASCADE's BRepTools::Read refused it)");
  out.unit = "model unit";
  out.notes.push_back("unit: BREP files carry none; coordinates are taken as they are");
  return shape;
}

std::size_t count(const TopoDS_Shape& shape, TopAbs_ShapeEnum type) {
  std::size_t n = 0;
  for (TopExp_Explorer e(shape, type); e.More(); e.Next()) ++n;
  return n;
}

/// Closed shells from loose faces or open shells: sewn within 1e-6 of the
/// shape's size (at least OCCT's 1e-6 mm), refused when a free edge remains.
std::vector<TopoDS_Shape> sew_into_solids(const std::string& path, const TopoDS_Shape& shape, CadSolid& out) {
  const std::size_t faces = count(shape, TopAbs_FACE);
  if (faces == 0) {
    const std::size_t edges = count(shape, TopAbs_EDGE);
    fail(path, "no solid and no face: the file holds " +
                   (edges ? std::to_string(edges) + " edges (curves) only" : std::string("no surface")) +
                   ", nothing that bounds a volume");
  }
  Bnd_Box box;
  BRepBndLib::Add(shape, box);
  const double tolerance = std::max(1e-6, box.IsVoid() ? 0.0 : 1e-6 * std::sqrt(box.SquareExtent()));
  BRepBuilderAPI_Sewing sewing(tolerance);
  for (TopExp_Explorer e(shape, TopAbs_FACE); e.More(); e.Next()) sewing.Add(e.Current());
  sewing.Perform();
  const TopoDS_Shape sewn = sewing.SewedShape();
  if (sewing.NbFreeEdges() > 0)
    fail(path, "no solid, and its " + std::to_string(faces) + " faces do not close: " +
                   std::to_string(sewing.NbFreeEdges()) + " free edges remain after sewing (tolerance " +
                   std::to_string(tolerance) + " mm): an open shell bounds no volume");
  std::vector<TopoDS_Shell> shells;
  for (TopExp_Explorer e(sewn, TopAbs_SHELL); e.More(); e.Next()) shells.push_back(TopoDS::Shell(e.Current()));
  if (shells.empty()) {  // one closed face (a sphere's) comes back alone
    TopoDS_Shell shell;
    BRep_Builder builder;
    builder.MakeShell(shell);
    for (TopExp_Explorer e(sewn, TopAbs_FACE); e.More(); e.Next()) builder.Add(shell, e.Current());
    shell.Closed(true);
    shells.push_back(shell);
  }
  std::vector<TopoDS_Shape> solids;
  for (const TopoDS_Shell& shell : shells) {
    BRepBuilderAPI_MakeSolid make(shell);
    if (!make.IsDone()) fail(path, "a sewn shell could not be made into a solid");
    ShapeFix_Solid fix;  // orients the shell to bound its volume
    fix.Init(make.Solid());
    fix.Perform();
    solids.push_back(fix.Solid());
  }
  if (solids.empty()) fail(path, "no solid, and sewing its " + std::to_string(faces) + " faces made no closed shell");
  out.notes.push_back("sewn: no solid in the file; its " + std::to_string(faces) + " faces were sewn into " +
                      std::to_string(solids.size()) + " closed shell(s) (tolerance " + std::to_string(tolerance) +
                      " mm, no free edge left)");
  return solids;
}

/// ": 1 \"pin\", 2 (unnamed)" when the file names any of the solids.
std::string solid_list(const std::vector<TopoDS_Shape>& solids, const CadSolid& out) {
  if (out.solid_names.empty()) return {};
  std::string list;
  for (std::size_t i = 0; i < solids.size(); ++i) {
    std::string name = "(unnamed)";
    for (const auto& [named, given] : out.solid_names)
      if (named.IsPartner(solids[i])) name = "\"" + given + "\"";  // the same solid, maybe placed elsewhere
    list += (i ? ", " : ": ") + std::to_string(i + 1) + " " + name;
  }
  return list;
}

/// The solid, checked; repaired with ShapeFix when the check fails.
TopoDS_Shape checked(const std::string& path, const TopoDS_Shape& solid, std::size_t index, CadSolid& out) {
  if (BRepCheck_Analyzer(solid).IsValid()) return solid;
  ShapeFix_Shape fix(solid);
  fix.Perform();
  if (!BRepCheck_Analyzer(fix.Shape()).IsValid())
    fail(path, "solid " + std::to_string(index) +
                   " is not valid (BRepCheck_Analyzer) and OpenCASCADE's ShapeFix could not repair it");
  out.notes.push_back("solid " + std::to_string(index) + ": not valid as read; repaired by ShapeFix_Shape");
  return fix.Shape();
}

}  // namespace

CadSolid read_cad_solid(const std::string& path, const LoadOptions& options) {
  if (!std::ifstream(path)) fail(path, "cannot open the file");
  CadSolid out;
  const std::string ext = lowercase_extension(path);
  TopoDS_Shape shape;
  try {
    if (ext == ".step" || ext == ".stp") {
      out.format = "STEP";
      shape = read_step(path, out);
    } else if (ext == ".iges" || ext == ".igs") {
      out.format = "IGES";
      shape = read_iges(path, out);
    } else {
      out.format = "BREP";
      shape = read_brep(path, out);
    }
    std::vector<TopoDS_Shape> solids;
    for (TopExp_Explorer e(shape, TopAbs_SOLID); e.More(); e.Next()) solids.push_back(e.Current());
    if (solids.empty()) solids = sew_into_solids(path, shape, out);
    const std::string listed = solid_list(solids, out);
    if (options.solid) {
      if (*options.solid < 1 || static_cast<std::size_t>(*options.solid) > solids.size())
        fail(path, "--solid " + std::to_string(*options.solid) + ": the file has " + std::to_string(solids.size()) +
                       " solid(s), numbered from 1" + listed);
      out.shape = checked(path, solids[static_cast<std::size_t>(*options.solid - 1)],
                          static_cast<std::size_t>(*options.solid), out);
      out.notes.push_back("solid " + std::to_string(*options.solid) + " of " + std::to_string(solids.size()) +
                          " (--solid)" + listed);
      return out;
    }
    for (std::size_t i = 0; i < solids.size(); ++i) solids[i] = checked(path, solids[i], i + 1, out);
    if (solids.size() == 1) {
      out.shape = solids[0];
      out.notes.push_back("1 solid, valid (BRepCheck_Analyzer)");
      return out;
    }
    // Several solids: their union (touching solids become one).
    TopTools_ListOfShape arguments, tools;
    arguments.Append(solids[0]);
    for (std::size_t i = 1; i < solids.size(); ++i) tools.Append(solids[i]);
    BRepAlgoAPI_Fuse fuse;
    fuse.SetArguments(arguments);
    fuse.SetTools(tools);
    fuse.Build();
    if (!fuse.IsDone()) fail(path, "the union of its " + std::to_string(solids.size()) + " solids failed (OCCT)");
    out.shape = fuse.Shape();
    out.notes.push_back(std::to_string(solids.size()) + " solids, valid (BRepCheck_Analyzer), united into " +
                        std::to_string(count(out.shape, TopAbs_SOLID)) +
                        " (BRepAlgoAPI_Fuse; --solid N takes one alone)" + listed);
    return out;
  } catch (const Standard_Failure& e) {
    fail(path, std::string("OpenCASCADE failed: ") + (e.GetMessageString() ? e.GetMessageString() : "no message"));
  }
}

}  // namespace sage::geometry::cad
