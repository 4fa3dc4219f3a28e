#pragma once
// Graph colouring for the plan's groups: patterns that conflict (render/plan.hpp) get
// different colours; each colour class fires as one device pattern.

#include <cstddef>
#include <vector>

namespace tp {

// DSatur (D. Brelaz, "New methods to color the vertices of a graph", Commun. ACM 22(4):
// 251-256, 1979): the uncoloured vertex with the most distinct colours among its
// neighbours next (ties: the most uncoloured neighbours, then the lowest index), given the
// least colour none of its neighbours has.  adj: each vertex's neighbours (symmetric, no
// self-loops).  Returns each vertex's colour, 0 up; deterministic.
std::vector<int> dsatur(const std::vector<std::vector<std::size_t>>& adj);

}  // namespace tp
