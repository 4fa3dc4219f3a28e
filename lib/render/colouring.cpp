#include "render/colouring.hpp"

namespace tp {

std::vector<int> dsatur(const std::vector<std::vector<std::size_t>>& adj) {
  const std::size_t n = adj.size();
  std::vector<int> colour(n, -1);
  std::vector<std::vector<char>> seen(n);  // seen[v][c]: a neighbour of v has colour c
  std::vector<int> saturation(n, 0), free_degree(n);
  for (std::size_t v = 0; v < n; ++v) free_degree[v] = static_cast<int>(adj[v].size());
  for (std::size_t done = 0; done < n; ++done) {
    std::size_t best = n;
    for (std::size_t v = 0; v < n; ++v) {
      if (colour[v] >= 0) continue;
      if (best == n || saturation[v] > saturation[best] ||
          (saturation[v] == saturation[best] && free_degree[v] > free_degree[best]))
        best = v;
    }
    int c = 0;
    while (static_cast<std::size_t>(c) < seen[best].size() &&
           seen[best][static_cast<std::size_t>(c)])
      ++c;
    colour[best] = c;
    for (const std::size_t u : adj[best]) {
      --free_degree[u];
      if (seen[u].size() <= static_cast<std::size_t>(c))
        seen[u].resize(static_cast<std::size_t>(c) + 1, 0);
      if (!seen[u][static_cast<std::size_t>(c)]) {
        seen[u][static_cast<std::size_t>(c)] = 1;
        ++saturation[u];
      }
    }
  }
  return colour;
}

}  // namespace tp
