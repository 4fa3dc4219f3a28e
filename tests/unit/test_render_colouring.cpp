// DSatur (lib/render/colouring.hpp): a proper colouring (no edge within a colour), colours
// 0 up without gaps, and the chromatic number where it is known in closed form: n for a
// complete graph, 2 for a bipartite one (DSatur is exact on bipartite graphs), 3 for an
// odd cycle, 1 for no edges.
#include <catch2/catch.hpp>

#include <algorithm>
#include <random>
#include <set>

#include "render/colouring.hpp"

using namespace tp;

namespace {

using Graph = std::vector<std::vector<std::size_t>>;

void add_edge(Graph& g, std::size_t a, std::size_t b) {
  g[a].push_back(b);
  g[b].push_back(a);
}

int colours(const std::vector<int>& c) {
  return c.empty() ? 0 : *std::max_element(c.begin(), c.end()) + 1;
}

void check_proper(const Graph& g, const std::vector<int>& c) {
  REQUIRE(c.size() == g.size());
  for (std::size_t v = 0; v < g.size(); ++v) {
    CHECK(c[v] >= 0);
    for (const std::size_t u : g[v]) CHECK(c[u] != c[v]);
  }
  const std::set<int> used(c.begin(), c.end());
  CHECK(static_cast<int>(used.size()) == colours(c));  // 0 .. k-1, none skipped
}

Graph cycle(std::size_t n) {
  Graph g(n);
  for (std::size_t v = 0; v < n; ++v) add_edge(g, v, (v + 1) % n);
  return g;
}

}  // namespace

TEST_CASE("colouring: DSatur's colours in closed form", "[render][colouring]") {
  CHECK(dsatur({}).empty());
  const Graph none(5);
  CHECK(dsatur(none) == std::vector<int>(5, 0));
  Graph complete(6);
  for (std::size_t a = 0; a < 6; ++a)
    for (std::size_t b = a + 1; b < 6; ++b) add_edge(complete, a, b);
  check_proper(complete, dsatur(complete));
  CHECK(colours(dsatur(complete)) == 6);
  for (const std::size_t n : {4, 6, 10}) {
    check_proper(cycle(n), dsatur(cycle(n)));
    CHECK(colours(dsatur(cycle(n))) == 2);
  }
  for (const std::size_t n : {3, 5, 9}) {
    check_proper(cycle(n), dsatur(cycle(n)));
    CHECK(colours(dsatur(cycle(n))) == 3);
  }
  // A crown graph (K_{n,n} less a perfect matching) defeats greedy colouring in index
  // order (n colours when the sides alternate); DSatur, exact on bipartite graphs, uses 2.
  const std::size_t n = 5;
  Graph crown(2 * n);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < n; ++j)
      if (i != j) add_edge(crown, 2 * i, 2 * j + 1);
  check_proper(crown, dsatur(crown));
  CHECK(colours(dsatur(crown)) == 2);
}

TEST_CASE("colouring: random graphs coloured properly, the same each time", "[render][colouring]") {
  std::mt19937 rng(39);
  for (int run = 0; run < 40; ++run) {
    const std::size_t n = std::uniform_int_distribution<std::size_t>(1, 60)(rng);
    const double p = std::uniform_real_distribution<double>(0, 0.5)(rng);
    Graph g(n);
    std::size_t degree = 0;
    for (std::size_t a = 0; a < n; ++a)
      for (std::size_t b = a + 1; b < n; ++b)
        if (std::bernoulli_distribution(p)(rng)) add_edge(g, a, b);
    for (const auto& adj : g) degree = std::max(degree, adj.size());
    const std::vector<int> c = dsatur(g);
    check_proper(g, c);
    CHECK(colours(c) <= static_cast<int>(degree) + 1);  // never more than greedy's bound
    CHECK(dsatur(g) == c);
  }
}
