// The contact-law registry (contact/law_table.hpp, contact/registry.hpp): the scenario's names,
// `sable info --models` and the build all come from the table, an unknown name is an error at
// every level, and a law is added by one struct and one row of a table: the DEM solver, the
// critical time step and the servo's stiffness then use it with no other change.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <set>
#include <string>
#include <string_view>

#include "sable/contact/registry.hpp"
#include "sable/core/error.hpp"
#include "sable/dem/dem_solver_impl.hpp"
#include "sable/loading/servo.hpp"
#include "sable/scenario/build.hpp"
#include "sable/scenario/config.hpp"
#include "sable/world/critical_time.hpp"

namespace sable {
namespace {

// --- A law added by a test: one struct ... --------------------------------------------------

// An undamped linear spring of a fixed stiffness, frictionless: the textbook harmonic
// collision, whose contact time and overlap are exact closed forms.
struct HookeNormal {
  static constexpr double kStiffness = 2.0e4;  // N/m
  static constexpr std::string_view kName = "test-hooke";
  static constexpr std::string_view kSummary = "undamped spring of 2e4 N/m (a test's law)";
  static constexpr bool kSpringConstants = false;
  static constexpr std::string_view kCriticalTimeName = "sqrt(m / 2k) of the test law";
  static NormalCoeffs coeffs(const PairParams&, const ContactModel&, double, double, double) {
    return {kStiffness, 0.0, 0.0, 0.0};
  }
  static double stiffness(const PairParams&, const ContactModel&, double, double) {
    return kStiffness;
  }
  static double tangent_stiffness(const PairParams&, const ContactModel&, double, double) {
    return kStiffness;
  }
  static double critical_time(const Material&, double, double mass, const ContactModel&) {
    return std::sqrt(0.5 * mass / kStiffness);
  }
};

// ... and one row.
using TestLaws = LawTable<HertzNormal, LinearNormal, HookeNormal>;

constexpr double kRadius = 1e-3, kDensity = 2500.0;

Material glass() {
  Material m;
  m.name = "glass";
  m.density = kDensity;
  m.young = 7e10;
  m.poisson = 0.22;
  m.restitution = 0.5;  // ignored by the Hooke law: it has no dashpot
  m.friction = 0.0;
  return m;
}

// Two spheres approaching head-on at 2 v along x, 0.1 R apart.
World<3> head_on(double v, double dt) {
  World<3> w;
  w.model.normal = TestLaws::id<HookeNormal>();
  w.model.tangential = TangentialModel::kNone;
  const MaterialIndex mi = w.materials.add(glass());
  w.materials.finalize();
  const double x = 1.05 * kRadius;
  w.particles.add(Space<3>::Vec(-x, 0, 0), kRadius, kDensity, mi, 1.0);
  w.particles.add(Space<3>::Vec(x, 0, 0), kRadius, kDensity, mi, 1.0);
  w.particles.v[0].x() = v;
  w.particles.v[1].x() = -v;
  w.gravity.setZero();
  w.dt = dt;
  w.neighbors.skin = 0.5 * kRadius;
  w.neighbors.domain_lo = Space<3>::Vec::Constant(-4 * kRadius);
  w.neighbors.domain_hi = Space<3>::Vec::Constant(4 * kRadius);
  return w;
}

TEST(LawRegistry, ATableFindsItsLawsByNameAndRow) {
  EXPECT_EQ(TestLaws::kSize, 3u);
  EXPECT_EQ(TestLaws::id<HookeNormal>().row, 2);
  ASSERT_TRUE(TestLaws::find("test-hooke").has_value());
  EXPECT_EQ(*TestLaws::find("test-hooke"), TestLaws::id<HookeNormal>());
  EXPECT_FALSE(TestLaws::find("hooke").has_value());
  EXPECT_FALSE(NormalLaws::find("test-hooke").has_value());  // the default table is untouched
  // The row picks the struct: visit returns each row's own name.
  for (std::uint8_t row = 0; row < TestLaws::kSize; ++row)
    EXPECT_EQ(TestLaws::visit(NormalModel{row}, []<class Law>() { return Law::kName; }),
              TestLaws::kNames[row]);
  EXPECT_THROW(TestLaws::visit(NormalModel{3}, []<class Law>() { return 0; }), std::out_of_range);
  // `sable models` for this table lists the added law with its summary.
  const auto rows = sub_model_rows<TestLaws>();
  EXPECT_EQ(rows[2].category, "normal");
  EXPECT_EQ(rows[2].name, HookeNormal::kName);
  EXPECT_EQ(rows[2].summary, HookeNormal::kSummary);
  EXPECT_FALSE(HookeNormal::kSpringConstants);  // so contact.kn and kt would be refused
}

// The added law drives a whole DEM collision through DemSolver<3, TestLaws>. For an undamped
// linear spring k between two spheres of mass m (m* = m/2) approaching at relative speed u:
// contact time pi sqrt(m*/k), largest overlap u sqrt(m*/k), restitution 1 (Landau & Lifshitz,
// Mechanics, sec. 21: a half period of the harmonic oscillator). Neither shipped law gives
// these: Hertz's contact time depends on u, and the linear law reads contact.kn (0 here).
// Tolerances: dt = t_c / 2000, and the contact's start and end are interpolated on the gap,
// so t_c is within O(dt) = 5e-4 relative (1e-3 allowed); velocity Verlet conserves the
// oscillator's energy to O(dt^2), so e and the overlap are within 1e-5 (1e-4 allowed). All
// three agree to better than 1e-6 as run.
TEST(LawRegistry, ALawAddedByAStructAndARowDrivesTheDemSolver) {
  const double v = 1.0;  // the gap of 0.1 R closes in 2,000 steps; the overlap peaks at 3 % of R
  const double m = kDensity * 4.0 / 3.0 * std::numbers::pi * std::pow(kRadius, 3);
  const double m_eff = 0.5 * m;
  const double t_c = std::numbers::pi * std::sqrt(m_eff / HookeNormal::kStiffness);
  World<3> w = head_on(v, t_c / 2000.0);

  DemSolver<3, TestLaws> solver(w);
  solver.initialize();
  auto gap = [&] { return (w.particles.x[1] - w.particles.x[0]).norm() - 2.0 * kRadius; };
  double g_prev = gap(), t_start = -1.0, t_end = -1.0, max_overlap = 0.0;
  for (int k = 0; k < 20000 && t_end < 0.0; ++k) {
    const double t0 = w.time;
    solver.step();
    const double g = gap();
    const double t_cross = t0 + w.dt * g_prev / (g_prev - g);
    if (t_start < 0.0 && g < 0.0) t_start = t_cross;
    if (t_start >= 0.0 && g >= 0.0) t_end = t_cross;
    max_overlap = std::max(max_overlap, -g);
    g_prev = g;
  }
  ASSERT_GT(t_end, 0.0) << "the grains never separated";
  EXPECT_NEAR((t_end - t_start) / t_c, 1.0, 1e-3);
  EXPECT_NEAR(max_overlap / (2.0 * v * std::sqrt(m_eff / HookeNormal::kStiffness)), 1.0, 1e-4);
  EXPECT_NEAR((w.particles.v[1].x() - w.particles.v[0].x()) / (2.0 * v), 1.0, 1e-4);
}

// The time-step check and the servo read the law through the same table.
TEST(LawRegistry, CriticalTimeAndServoStiffnessComeFromTheRow) {
  World<3> w = head_on(0.0, 1e-7);
  const double m = w.particles.mass[0];
  EXPECT_DOUBLE_EQ(critical_time<TestLaws>(w), std::sqrt(0.5 * m / HookeNormal::kStiffness));
  EXPECT_EQ(critical_time_name<TestLaws>(w), HookeNormal::kCriticalTimeName);
  // A grain pressed 1 um into a floor: the servo's stiffness is the law's, its damping 0.
  World<3> f;
  f.model.normal = TestLaws::id<HookeNormal>();
  const MaterialIndex mi = f.materials.add(glass());
  f.materials.finalize();
  Wall<3> floor;
  floor.name = "floor";
  floor.point.setZero();
  floor.set_plane(Space<3>::Vec(0, 0, 1));
  floor.material = mi;
  f.walls.push_back(floor);
  f.particles.add(Space<3>::Vec(0, 0, kRadius - 1e-6), kRadius, kDensity, mi, 1.0);
  f.gravity.setZero();
  f.dt = 1e-7;
  f.neighbors.skin = 0.5 * kRadius;
  f.neighbors.domain_lo = Space<3>::Vec::Constant(-4 * kRadius);
  f.neighbors.domain_hi = Space<3>::Vec::Constant(4 * kRadius);
  DemSolver<3, TestLaws>(f).initialize();
  const WallResponse r = wall_response<TestLaws>(f, 0);
  EXPECT_EQ(r.stiffness, HookeNormal::kStiffness);
  EXPECT_EQ(r.damping, 0.0);
}

// --- The shipped table: names, rows, messages -----------------------------------------------

TEST(LawRegistry, ModelsListingHasOneNormalRowPerLaw) {
  std::set<std::string_view> names;
  std::size_t normal_rows = 0;
  for (const SubModelEntry& e : kContactSubModels) {
    if (e.category != "normal") continue;
    ASSERT_LT(static_cast<std::size_t>(e.code), NormalLaws::kSize);
    EXPECT_EQ(e.name, NormalLaws::kNames[static_cast<std::size_t>(e.code)]);
    EXPECT_FALSE(e.summary.empty());
    names.insert(e.name);
    ++normal_rows;
  }
  EXPECT_EQ(normal_rows, NormalLaws::kSize);
  EXPECT_EQ(names.size(), NormalLaws::kSize);       // names are unique
  EXPECT_EQ(NormalLaws::id<HertzNormal>().row, 0);  // the default law is row 0
}

const char* kScenario = R"([simulation]
dimension = 3
[domain]
lo = [0, 0, 0]
hi = [0.01, 0.01, 0.01]
[[material]]
name = "g"
density = 2500.0
young = 1e8
poisson = 0.3
restitution = 0.5
friction = 0.4
[[grains]]
generator = "lattice"
material = "g"
radius = 1e-3
spacing = 2.5e-3
region = { box = { lo = [0, 0, 0], hi = [0.01, 0.01, 0.01] } }
count = 8
[contact]
CONTACT
[[stage]]
steps = 1
)";

// kScenario with contact.normal = `normal` (and the spring constants a law may require).
std::string scenario_with(const std::string& normal, bool springs = false) {
  std::string s = kScenario;
  const std::string contact =
      "normal = \"" + normal + "\"" + (springs ? "\nkn = 1e4\nkt = 1e4" : "");
  s.replace(s.find("CONTACT"), 7, contact);
  return s;
}

TEST(LawRegistry, TheParserOffersEveryRegisteredName) {
  for (std::string_view name : NormalLaws::kNames) {
    const bool springs = NormalLaws::visit(*NormalLaws::find(name),
                                           []<class Law>() { return Law::kSpringConstants; });
    const ScenarioConfig cfg =
        parse_scenario(scenario_with(std::string(name), springs), "test.toml");
    EXPECT_EQ(cfg.contact.normal, name);
  }
  try {
    (void)parse_scenario(scenario_with("hooke"), "test.toml");
    FAIL() << "an unknown law was accepted";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("test.toml:21"), std::string::npos) << msg;
    EXPECT_NE(msg.find("normal"), std::string::npos) << msg;
    for (std::string_view name : NormalLaws::kNames)
      EXPECT_NE(msg.find("\"" + std::string(name) + "\""), std::string::npos) << msg;
  }
}

// A ContactConfig changed after parsing (a program building its own) is checked again by the
// build: an unknown name is an error naming the key, never a silent Hertz.
TEST(LawRegistry, TheBuildRefusesAnUnknownNameInsteadOfFallingBack) {
  ScenarioConfig cfg = parse_scenario(scenario_with("hertz"), "test.toml");
  for (const char* category : {"normal", "tangential", "rolling", "cohesion"}) {
    ScenarioConfig bad = cfg;
    std::string& field = category == std::string_view("normal")       ? bad.contact.normal
                         : category == std::string_view("tangential") ? bad.contact.tangential
                         : category == std::string_view("rolling")    ? bad.contact.rolling
                                                                      : bad.contact.cohesion;
    field = "nonesuch";
    World<3> w;
    try {
      build_model(bad, w);
      ADD_FAILURE() << category << ": an unknown name was accepted";
    } catch (const InputError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find(std::string("contact.") + category + " = \"nonesuch\""), std::string::npos)
          << msg;
      for (std::string_view name : sub_model_names(category))
        EXPECT_NE(msg.find("\"" + std::string(name) + "\""), std::string::npos) << msg;
    }
  }
}

}  // namespace
}  // namespace sable
