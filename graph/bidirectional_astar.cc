#include "graph/bidirectional_astar.h"

#include <algorithm>
#include <functional>
#include <limits>
#include <queue>
#include <utility>

namespace splam::graph {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr std::size_t kNone = std::numeric_limits<std::size_t>::max();

using Entry = std::pair<double, std::size_t>;  // (key, vertex)
using Queue = std::priority_queue<Entry, std::vector<Entry>, std::greater<>>;

// One direction of the search: reduced distances, parents, settled flags, the queue.
struct Side {
  explicit Side(std::size_t n) : distance(n, kInf), parent(n, kNone), settled(n, false) {}
  std::vector<double> distance;
  std::vector<std::size_t> parent;
  std::vector<bool> settled;
  Queue queue;

  // Smallest key of a vertex not yet settled (entries of settled vertices are dropped).
  double Top() {
    while (!queue.empty() && settled[queue.top().second]) queue.pop();
    return queue.empty() ? kInf : queue.top().first;
  }
  void Relax(std::size_t v, std::size_t from, double d) {
    if (d < distance[v]) {
      distance[v] = d;
      parent[v] = from;
      queue.push({d, v});
    }
  }
};

}  // namespace

std::optional<GraphPath> BidirectionalAStar(const ExplorationGraph& graph, Vertex source,
                                            const std::vector<Vertex>& targets,
                                            SearchStats* stats) {
  const std::size_t n = graph.num_nodes();
  if (targets.empty() || source >= n) return std::nullopt;
  // Vertex n is the virtual target T, joined to every target by a zero-length edge.
  const std::size_t t_star = n;
  std::vector<bool> is_target(n, false);
  for (const Vertex t : targets) {
    if (t < n) is_target[t] = true;
  }
  if (is_target[source]) return GraphPath{{source}, 0.0};

  auto position = [&](std::size_t v) { return graph[v].configuration.translation(); };
  const Eigen::Vector2d s = position(source);
  double pi_r_star = kInf;  // |s - t| of the nearest target: a consistent estimate of d(s, T)
  for (const Vertex t : targets) {
    if (t < n) pi_r_star = std::min(pi_r_star, (position(t) - s).norm());
  }
  // Potentials p(v) = (pi_f(v) - pi_r(v)) / 2, computed once per vertex when first needed.
  std::vector<double> potential(n + 1, kInf);
  potential[t_star] = -0.5 * pi_r_star;
  auto p = [&](std::size_t v) {
    if (potential[v] == kInf) {
      double pi_f = kInf;
      for (const Vertex t : targets) {
        if (t < n) pi_f = std::min(pi_f, (position(t) - position(v)).norm());
      }
      potential[v] = 0.5 * (pi_f - (position(v) - s).norm());
    }
    return potential[v];
  };

  Side forward(n + 1), backward(n + 1);
  forward.Relax(source, kNone, 0.0);
  backward.Relax(t_star, kNone, 0.0);
  double best = kInf;  // shortest s-T connection found, in reduced lengths
  std::size_t meet_forward = kNone, meet_backward = kNone;
  auto connect = [&](std::size_t u, std::size_t v, double reduced_length) {
    // u reached forward, v backward, joined by an edge u -> v of this reduced length.
    const double total = forward.distance[u] + reduced_length + backward.distance[v];
    if (total < best) best = total, meet_forward = u, meet_backward = v;
  };
  int expanded = 0;
  while (true) {
    const double top_f = forward.Top(), top_b = backward.Top();
    if (top_f == kInf || top_b == kInf || top_f + top_b >= best) break;
    if (top_f <= top_b) {  // expand forward
      const std::size_t u = forward.queue.top().second;
      forward.queue.pop();
      forward.settled[u] = true;
      ++expanded;
      if (is_target[u]) connect(u, t_star, p(t_star) - p(u));  // u -> T, length 0
      graph.ForEachNeighbour(u, [&](Vertex v, const EdgeData& edge) {
        const double reduced = edge.length_m - p(u) + p(v);
        forward.Relax(v, u, forward.distance[u] + reduced);
        if (backward.distance[v] < kInf) connect(u, v, reduced);
      });
    } else {  // expand backward
      const std::size_t v = backward.queue.top().second;
      backward.queue.pop();
      backward.settled[v] = true;
      ++expanded;
      if (v == t_star) {
        for (const Vertex t : targets) {
          if (t >= n) continue;
          const double reduced = p(t_star) - p(t);  // t -> T, length 0
          backward.Relax(t, t_star, reduced);
          if (forward.distance[t] < kInf) connect(t, t_star, reduced);
        }
        continue;
      }
      graph.ForEachNeighbour(v, [&](Vertex u, const EdgeData& edge) {
        const double reduced = edge.length_m - p(u) + p(v);  // u -> v
        backward.Relax(u, v, backward.distance[v] + reduced);
        if (forward.distance[u] < kInf) connect(u, v, reduced);
      });
    }
  }
  if (stats != nullptr) stats->expanded = expanded;
  if (best == kInf) return std::nullopt;

  // source .. meet_forward, then meet_backward .. T (T itself left out).
  GraphPath path;
  for (std::size_t v = meet_forward; v != kNone; v = forward.parent[v]) path.vertices.push_back(v);
  std::reverse(path.vertices.begin(), path.vertices.end());
  for (std::size_t v = meet_backward; v != t_star && v != kNone; v = backward.parent[v])
    path.vertices.push_back(v);
  for (std::size_t k = 1; k < path.vertices.size(); ++k) {
    const EdgeData* edge = graph.Edge(path.vertices[k - 1], path.vertices[k]);
    path.length_m += edge != nullptr ? edge->length_m : 0.0;
  }
  return path;
}

}  // namespace splam::graph
