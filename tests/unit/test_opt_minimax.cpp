// optimize_mode's steps (opt/minimax.hpp, minimax::Search): a candidate from each start
// and each LP seed, the best kept, the polish never worse, the bound honoured, the failure
// named, and the steps composed giving optimize_mode's answer.
#include <catch2/catch.hpp>

#include <cmath>
#include <optional>
#include <set>
#include <string>

#include "core/error.hpp"
#include "opt/minimax.hpp"

using namespace tp;
using minimax::Candidate;
using minimax::Search;

TEST_CASE("minimax search: a candidate from each start and each LP seed", "[opt][minimax]") {
  const Setup s;  // the paper's 8 electrodes: mirror-symmetric
  Search v(s, "SAI", OptimizeOptions{});
  v.surrogate();
  CHECK(v.counts().starts == 2);  // the anode and the cathode
  CHECK(v.counts().iterations > 0);
  const std::size_t from_starts = v.candidates().size();
  CHECK(from_starts >= 1);
  CHECK(from_starts <= 2);
  v.lp_seeds();
  CHECK(v.counts().lp_solves == 4);  // electrodes 0-3: the others are their mirror images
  std::set<std::string> labels;
  for (const Candidate& c : v.candidates()) {
    labels.insert(c.label);
    CHECK(std::isfinite(c.ratio));
    CHECK(v.assess(c.z, c.label).ratio == c.ratio);  // its ratio is its weights' own
  }
  for (int i = 0; i < 4; ++i) CHECK(labels.count("lp-under-electrode-" + std::to_string(i)) == 1);
  CHECK(labels.count("lp-under-electrode-4") == 0);
  v.keep_best();
  REQUIRE(v.candidates().size() == 3);  // polished_candidates
  for (std::size_t i = 1; i < v.candidates().size(); ++i)
    CHECK(v.candidates()[i - 1].ratio <= v.candidates()[i].ratio);

  // An array with no mirror: a seed under every electrode.
  Setup skew;
  skew.array.positions_mm = {-2.0, -1.0, 0.0, 1.0, 3.0};
  skew.array.pitch_mm.reset();
  Search u(skew, "PC", OptimizeOptions{});
  u.lp_seeds();
  CHECK(u.counts().lp_solves == 5);
}

TEST_CASE("minimax search: the polish is never worse, and honours a minimum target AF",
          "[opt][minimax]") {
  const Setup s;
  for (const std::string mode : {"RA", "SAI", "PC"}) {
    Search v(s, mode, OptimizeOptions{});
    v.surrogate();
    v.lp_seeds();
    v.keep_best();
    for (const Candidate& c : v.candidates()) {
      const Candidate p = v.polish(c);
      INFO(mode << " " << c.label << ": " << c.ratio << " polished " << p.ratio);
      CHECK(p.ratio <= c.ratio);
      CHECK(p.label == c.label);
      CHECK(v.assess(p.z, p.label).ratio == p.ratio);
    }
  }
  // With a minimum target AF only LP solutions count: the answer reaches it.
  OptimizeOptions bounded;
  bounded.min_target_af = 1.0;
  Search b(s, "PC", bounded);
  const OptimizeResult r = b.run();
  CHECK(r.target_max_af >= 1.0 * (1 - 1e-9));
  CHECK(r.best_start != "");
}

TEST_CASE("minimax search: no weights reach the target AF asked, named", "[opt][minimax]") {
  const Setup s;
  OptimizeOptions o;
  o.min_target_af = 1000.0;
  Search v(s, "SAI", o);
  try {
    v.run();
    FAIL("accepted");
  } catch (const Error& e) {
    CHECK(e.code() == ExitCode::bad_input);
    CHECK_THAT(e.what(), Catch::Contains("no weights reach a target AF of 1000 V/ms at 2 mA"));
    CHECK_THAT(e.what(), Catch::Contains("the most selective weights reach"));
  }
  OptimizeOptions bad;
  bad.max_current_mA = 0.0;
  CHECK_THROWS_WITH(Search(s, "SAI", bad), Catch::Contains("max current must be > 0 mA"));
}

TEST_CASE("minimax search: the steps composed give optimize_mode's answer, bit for bit",
          "[opt][minimax]") {
  const Setup s;
  for (const std::string mode : {"RA", "SAI", "PC"}) {
    const OptimizeResult direct = optimize_mode(s, mode, OptimizeOptions{});
    Search v(s, mode, OptimizeOptions{});
    v.surrogate();
    v.lp_seeds();
    v.keep_best();
    std::optional<Candidate> best;
    for (const Candidate& c : v.candidates()) {
      const Candidate p = v.polish(c);
      if (std::isfinite(p.ratio) && (!best || p.ratio < best->ratio)) best = p;
    }
    REQUIRE(best);
    const OptimizeResult stepped = v.finish(*best);
    INFO(mode);
    CHECK(stepped.weights == direct.weights);
    CHECK(stepped.ratio == direct.ratio);
    CHECK(stepped.best_start == direct.best_start);
    CHECK(stepped.lp_solves == direct.lp_solves);
    CHECK(stepped.starts == direct.starts);
  }
}
