// CAD solids through OpenCASCADE: files made here with OCCT, read back
// and checked against OCCT's own answers (point classification, areas,
// volumes) and the closed forms of the solids.
#include <sage/geometry/cad_model.hpp>
#include <sage/geometry/model.hpp>
#include <sage/tape/evaluator.hpp>
#include <sage/tape/tape.hpp>

#include <gtest/gtest.h>
#include <cad_fixtures.hpp>
#include <test_files.hpp>

#include <BRepBuilderAPI_MakeEdge.hxx>
#include <BRepBuilderAPI_Transform.hxx>
#include <BRepClass3d_SolidClassifier.hxx>
#include <BRep_Builder.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Compound.hxx>

#include <cmath>
#include <fstream>
#include <random>

namespace sage::geometry {
namespace {

using test::scratch_dir;

std::string path_of(const std::string& name) { return (scratch_dir() / name).string(); }

std::string block_step() {
  static const std::string path = [] {
    const std::string p = path_of("block.step");
    test::write_step(test::block_with_channel(), p);
    return p;
  }();
  return path;
}

/// The volume the model's triangles enclose (divergence theorem).
double enclosed_volume(const Model& m) {
  double v = 0;
  for (const auto& t : m.surface->triangles) {
    const auto &a = m.surface->points[t[0]], &b = m.surface->points[t[1]], &c = m.surface->points[t[2]];
    v +=
        (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0])) /
        6;
  }
  return v;
}

double total_area(const Model& m) {
  double a = 0;
  for (const ModelFace& f : m.faces) a += f.area;
  return a;
}

std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "(no error)";
}

const double kChannelVolume = 4.0 - M_PI * 0.16;

TEST(CadModel, BlockWithChannelFacesAreasAndVolume) {
  const Model m = load_model(block_step());
  EXPECT_EQ(m.dimension, 3);
  EXPECT_EQ(m.unit, "millimetre");
  ASSERT_EQ(m.faces.size(), 7u);
  std::size_t planes = 0, cylinders = 0;
  for (const ModelFace& f : m.faces) {
    if (f.surface == "plane") {
      ++planes;
      ASSERT_TRUE(f.normal);
      // Outward: the normal points from the block's centre to the face.
      const double out =
          (*f.normal)[0] * f.centroid[0] + (*f.normal)[1] * f.centroid[1] + (*f.normal)[2] * (f.centroid[2] - 0.5);
      EXPECT_GT(out, 0.4);
      const bool cap = std::abs((*f.normal)[2]) > 0.5;
      EXPECT_NEAR(f.area, cap ? 4 - M_PI * 0.16 : 2.0, 1e-9);
    }
    if (f.surface == "cylinder") {
      ++cylinders;
      EXPECT_NEAR(*f.radius, 0.4, 1e-12);
      EXPECT_NEAR(std::abs((*f.axis)[2]), 1.0, 1e-12);
      EXPECT_NEAR(f.area, 2 * M_PI * 0.4, 1e-9);
    }
  }
  EXPECT_EQ(planes, 6u);
  EXPECT_EQ(cylinders, 1u);
  // Every triangle carries a face, every face has triangles.
  ASSERT_EQ(m.triangle_faces.size(), m.surface->triangles.size());
  std::vector<int> per_face(8, 0);
  for (std::uint32_t f : m.triangle_faces) {
    ASSERT_GE(f, 1u);
    ASSERT_LE(f, 7u);
    ++per_face[f];
  }
  for (int f = 1; f <= 7; ++f) EXPECT_GT(per_face[static_cast<std::size_t>(f)], 0) << f;
  // The triangles lie within the deflection of the faces: the volume they
  // enclose is off by at most deflection x area.
  const double deflection = 1e-3 * std::sqrt(4 + 4 + 1);
  EXPECT_NEAR(enclosed_volume(m), kChannelVolume, deflection * total_area(m));
  EXPECT_LT(std::abs(enclosed_volume(m) - kChannelVolume), 0.3 * deflection * total_area(m));
}

TEST(CadModel, SignsAgreeWithOcctClassifierAt10000Points) {
  const TopoDS_Shape solid = test::block_with_channel();
  const Model m = load_model(block_step());
  const double deflection = 1e-3 * std::sqrt(9.0);
  const Tape tape(m.field, 3);
  Evaluator<double> eval(tape);
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> x(-1.2, 1.2), z(-0.2, 1.2);
  int inside = 0, compared = 0, mismatches = 0;
  for (int k = 0; k < 10000; ++k) {
    const std::array<double, 3> p{x(rng), x(rng), z(rng)};
    // Points within twice the deflection of the exact surface are ON for
    // the classifier: the tessellation may put them on either side.
    BRepClass3d_SolidClassifier classifier(solid, gp_Pnt(p[0], p[1], p[2]), 2 * deflection);
    const TopAbs_State state = classifier.State();
    if (state == TopAbs_ON) continue;
    ++compared;
    const bool in = state == TopAbs_IN;
    inside += in;
    const double w = eval.at(p);
    if ((w > 0) != in) ++mismatches;
  }
  EXPECT_GT(compared, 9500);
  EXPECT_GT(inside, 1500);
  EXPECT_EQ(mismatches, 0);
}

TEST(CadModel, CoordinatesInTheFilesUnit) {
  // The block 25.4 times larger in OCCT's millimetres, written in inches:
  // read back, it is the block again, in inches.
  gp_Trsf scale;
  scale.SetScale(gp_Pnt(0, 0, 0), 25.4);
  const TopoDS_Shape inches = BRepBuilderAPI_Transform(test::block_with_channel(), scale).Shape();
  const std::string path = path_of("block_inches.stp");
  test::write_step(inches, path, "INCH");
  const Model m = load_model(path);
  EXPECT_EQ(m.unit, "inch");
  ASSERT_EQ(m.faces.size(), 7u);
  for (const ModelFace& f : m.faces) {
    if (f.surface == "cylinder") {
      EXPECT_NEAR(*f.radius, 0.4, 1e-9);
    }
  }
  EXPECT_NEAR(enclosed_volume(m), kChannelVolume, 1e-2);
  EXPECT_NE(message_of([&] { describe_face(m, 1); }).find("(no error)"), std::string::npos);
}

TEST(CadModel, IgesAndBrepGiveTheSameSolid) {
  const Model step = load_model(block_step());
  for (const std::string name : {"block.igs", "block.brep"}) {
    const std::string path = path_of(name);
    if (name.ends_with(".igs"))
      test::write_iges(test::block_with_channel(), path);
    else
      test::write_brep(test::block_with_channel(), path);
    const Model m = load_model(path);
    EXPECT_EQ(m.faces.size(), 7u) << name;
    EXPECT_NEAR(enclosed_volume(m), enclosed_volume(step), 1e-3) << name;
    EXPECT_NEAR(total_area(m), total_area(step), 1e-9) << name;
  }
}

TEST(CadModel, FaceQueries) {
  const Model m = load_model(block_step());
  const std::vector<std::size_t> channel = faces_matching(m, "cylinder radius 0.4");
  ASSERT_EQ(channel.size(), 1u);
  EXPECT_EQ(m.faces[channel[0] - 1].surface, "cylinder");
  EXPECT_EQ(faces_matching(m, "any radius 0.4"), channel);
  EXPECT_EQ(faces_matching(m, "cylinder axis 0 0 -1"), channel);  // either sense
  const std::vector<std::size_t> top = faces_matching(m, "plane normal 0 0 2");
  ASSERT_EQ(top.size(), 1u);
  EXPECT_NEAR(m.faces[top[0] - 1].centroid[2], 1.0, 1e-12);
  EXPECT_EQ(faces_matching(m, "plane").size(), 6u);
  EXPECT_EQ(faces_matching(m, "plane normal 0 0 -1").size(), 1u);
  EXPECT_NE(message_of([&] { faces_matching(m, "cone"); }).find("no cone face"), std::string::npos);
  EXPECT_NE(message_of([&] { faces_matching(m, "cylinder radius 3"); }).find("radius: 0.4"), std::string::npos);
  EXPECT_NE(message_of([&] { faces_matching(m, "disk"); }).find("start with a surface type"), std::string::npos);
  EXPECT_NE(message_of([&] { faces_matching(m, "plane normal 0 1"); }).find("needs 3 numbers"), std::string::npos);
  EXPECT_NE(message_of([&] { faces_matching(m, "plane shade red"); }).find("unknown condition"), std::string::npos);
  EXPECT_NE(message_of([&] { faces_selector(m, {8}); }).find("faces 1..7"), std::string::npos);
  // The selector vanishes on its face and nowhere else on the boundary:
  // at each triangle's centroid moved onto its face's exact surface.
  const Tape tape(faces_selector(m, channel), 3);
  Evaluator<double> eval(tape);
  for (std::size_t t = 0; t < m.surface->triangles.size(); ++t) {
    const auto& tri = m.surface->triangles[t];
    std::array<double, 3> c{};
    for (int a = 0; a < 3; ++a)
      c[a] = (m.surface->points[tri[0]][a] + m.surface->points[tri[1]][a] + m.surface->points[tri[2]][a]) / 3;
    ASSERT_TRUE(m.faces[m.triangle_faces[t] - 1].exact_surface);
    c = test::onto_surface(*m.faces[m.triangle_faces[t] - 1].exact_surface, c);
    const double s = eval.at(c);
    if (m.triangle_faces[t] == channel[0])
      EXPECT_LT(std::abs(s), 1e-12) << t;
    else
      EXPECT_GT(std::abs(s), 1e-4) << t;
  }
}

TEST(CadModel, FaceNamesFromTheFile) {
  // Name the channel and the top as a CAD system would, in the STEP file.
  const TopoDS_Shape block = test::block_with_channel();
  const Model plain = load_model(block_step());
  const std::size_t channel = faces_matching(plain, "cylinder").at(0),
                    top = faces_matching(plain, "plane normal 0 0 1").at(0);
  std::vector<std::string> names(plain.faces.size());
  names[channel - 1] = "channel";
  names[top - 1] = "lid";
  const std::string path = path_of("named.step");
  test::write_step(block, path, "MM", STEPControl_AsIs, names);
  const Model m = load_model(path);
  EXPECT_EQ(m.faces[channel - 1].name, "channel");
  EXPECT_EQ(m.faces[top - 1].name, "lid");
  EXPECT_EQ(faces_matching(m, "channel"), std::vector<std::size_t>{channel});
  EXPECT_NE(describe_face(m, top).find("\"lid\""), std::string::npos);
  bool noted = false;
  for (const std::string& note : m.notes) noted = noted || note.find("2 of 7 faces named") != std::string::npos;
  EXPECT_TRUE(noted);
}

TEST(CadModel, FaceColoursFromTheFile) {
  // The block grey, its channel red: the solid's colour goes to every
  // face, the channel's own wins on it.
  const Model plain = load_model(block_step());
  const int channel = static_cast<int>(faces_matching(plain, "cylinder").at(0));
  const std::string path = path_of("coloured.step");
  test::write_coloured_step(test::block_with_channel(), path, std::array<double, 3>{0.5, 0.5, 0.5},
                            {{channel, {1.0, 0.0, 0.0}}});
  const Model m = load_model(path);
  ASSERT_EQ(m.faces.size(), plain.faces.size());
  for (std::size_t f = 1; f <= m.faces.size(); ++f)
    EXPECT_EQ(m.faces[f - 1].colour, static_cast<int>(f) == channel ? "#ff0000" : "#808080") << f;
  EXPECT_EQ(faces_matching(m, "any colour #FF0000"), std::vector<std::size_t>{static_cast<std::size_t>(channel)});
  EXPECT_EQ(faces_matching(m, "plane colour #808080").size(), 6u);
  EXPECT_NE(describe_face(m, static_cast<std::size_t>(channel)).find("colour #ff0000"), std::string::npos);
  EXPECT_NE(message_of([&] { faces_matching(m, "any colour #00ff00"); }).find("their colours: #808080, #ff0000"),
            std::string::npos);
  EXPECT_NE(message_of([&] { faces_matching(m, "any colour red"); }).find("needs a colour as #rrggbb"),
            std::string::npos);
  bool noted = false;
  for (const std::string& n : m.notes) noted = noted || n.find("7 of 7 faces coloured") != std::string::npos;
  EXPECT_TRUE(noted);
}

TEST(CadModel, LooseFacesAreSewnIntoASolid) {
  // A sphere's surface without its solid (a shell-based surface model).
  const TopoDS_Shape sphere = BRepPrimAPI_MakeSphere(gp_Pnt(0, 0, 0), 1.0).Shell();
  const std::string path = path_of("sphere_shell.step");
  test::write_step(sphere, path, "MM", STEPControl_ShellBasedSurfaceModel);
  const Model m = load_model(path);
  bool sewn = false;
  for (const std::string& note : m.notes) sewn = sewn || note.rfind("sewn:", 0) == 0;
  EXPECT_TRUE(sewn);
  ASSERT_EQ(m.faces.size(), 1u);
  EXPECT_EQ(m.faces[0].surface, "sphere");
  EXPECT_NEAR(*m.faces[0].radius, 1.0, 1e-12);
  EXPECT_NEAR(m.faces[0].area, 4 * M_PI, 1e-9);
  EXPECT_NEAR(enclosed_volume(m), 4 * M_PI / 3, 4 * M_PI * 2e-3 * std::sqrt(3.0));
  const Tape tape(m.field, 3);
  Evaluator<double> eval(tape);
  EXPECT_GT(eval.at({0.1, 0.2, 0.3}), 0);
  EXPECT_LT(eval.at({0.9, 0.9, 0.0}), 0);
}

TEST(CadModel, TorusFaceAndVolume) {
  const TopoDS_Shape torus = BRepPrimAPI_MakeTorus(gp_Ax2(gp_Pnt(0, 0, 0), gp_Dir(0, 0, 1)), 2.0, 0.5).Shape();
  const std::string path = path_of("torus.step");
  test::write_step(torus, path);
  const Model m = load_model(path);
  ASSERT_EQ(m.faces.size(), 1u);
  EXPECT_EQ(m.faces[0].surface, "torus");
  EXPECT_NEAR(*m.faces[0].radius, 2.0, 1e-12);
  EXPECT_NEAR(*m.faces[0].minor_radius, 0.5, 1e-12);
  const double volume = 2 * M_PI * M_PI * 2.0 * 0.25;
  EXPECT_NEAR(enclosed_volume(m), volume, m.faces[0].area * 1e-3 * std::hypot(5.0, 5.0, 1.0));
  EXPECT_EQ(faces_matching(m, "torus radius 2").size(), 1u);
}

TEST(CadModel, SeveralSolidsAreUnitedOrPicked) {
  TopoDS_Compound two;
  BRep_Builder builder;
  builder.MakeCompound(two);
  builder.Add(two, BRepPrimAPI_MakeBox(gp_Pnt(0, 0, 0), 1, 1, 1).Shape());
  builder.Add(two, BRepPrimAPI_MakeBox(gp_Pnt(2, 0, 0), 1, 2, 1).Shape());
  const std::string path = path_of("two_boxes.step");
  test::write_step(two, path, "MM", STEPControl_AsIs, {}, {"cube", "slab"});
  const Model both = load_model(path);
  EXPECT_NEAR(enclosed_volume(both), 3.0, 1e-12);
  EXPECT_EQ(both.faces.size(), 12u);
  bool listed = false;  // the file's names for its solids, for --solid
  for (const std::string& n : both.notes) listed = listed || n.find(": 1 \"cube\", 2 \"slab\"") != std::string::npos;
  EXPECT_TRUE(listed);
  LoadOptions second;
  second.solid = 2;
  const Model one = load_model(path, second);
  EXPECT_NEAR(enclosed_volume(one), 2.0, 1e-12);
  second.solid = 3;
  EXPECT_NE(message_of([&] {
              load_model(path, second);
            }).find("--solid 3: the file has 2 solid(s), numbered from 1: 1 \"cube\", 2 \"slab\""),
            std::string::npos);
}

TEST(CadModel, BadFilesNameTheFileAndWhatIsWrong) {
  auto write = [](const std::string& name, const std::string& text) {
    const std::string p = path_of(name);
    std::ofstream(p) << text;
    return p;
  };
  const std::string garbage = write("garbage.step", "{\"not\": \"a STEP file\"}\n");
  std::string what = message_of([&] { load_model(garbage); });
  EXPECT_NE(what.find(garbage + ": not a readable STEP file"), std::string::npos) << what;
  EXPECT_EQ(what.find("JSON"), std::string::npos) << what;
  what = message_of([&] { load_model(write("garbage.igs", "hello\n")); });
  EXPECT_NE(what.find("IGES"), std::string::npos) << what;
  what = message_of([&] { load_model(write("garbage.brep", "hello\n")); });
  EXPECT_NE(what.find("not a readable BREP file"), std::string::npos) << what;
  what = message_of([&] { load_model(path_of("missing.step")); });
  EXPECT_NE(what.find("cannot open"), std::string::npos) << what;
  what = message_of([&] { load_model(write("part.xyz", "1 2 3\n")); });
  EXPECT_NE(what.find("unknown file type '.xyz'"), std::string::npos) << what;
  EXPECT_NE(what.find(".step"), std::string::npos) << what;
  // Curves only: nothing bounds a volume.
  const std::string curve = path_of("curve.brep");
  test::write_brep(BRepBuilderAPI_MakeEdge(gp_Pnt(0, 0, 0), gp_Pnt(1, 0, 0)).Edge(), curve);
  what = message_of([&] { load_model(curve); });
  EXPECT_NE(what.find("no solid and no face"), std::string::npos) << what;
  // An open box: five faces that cannot close.
  TopoDS_Compound open;
  BRep_Builder builder;
  builder.MakeCompound(open);
  int n = 0;
  for (TopExp_Explorer e(BRepPrimAPI_MakeBox(1, 1, 1).Shape(), TopAbs_FACE); e.More(); e.Next())
    if (n++ < 5) builder.Add(open, e.Current());
  const std::string open_path = path_of("open_box.brep");
  test::write_brep(open, open_path);
  what = message_of([&] { load_model(open_path); });
  EXPECT_NE(what.find("free edges remain after sewing"), std::string::npos) << what;
}

}  // namespace
}  // namespace sage::geometry
