#include <asf/errors.h>
#include <asf/graph/multigraph.h>

#include <fstream>
#include <sstream>

namespace asf::graph {

bool Multigraph::connected() const {
  if (n <= 0) return false;
  const auto inc = incidence();
  std::vector<char> seen(n, 0);
  std::vector<int> stack{0};
  seen[0] = 1;
  int count = 1;
  while (!stack.empty()) {
    const int a = stack.back();
    stack.pop_back();
    for (int e : inc[a]) {
      const int b = edges[e].u == a ? edges[e].v : edges[e].u;
      if (!seen[b]) {
        seen[b] = 1;
        ++count;
        stack.push_back(b);
      }
    }
  }
  return count == n;
}

std::vector<int> Multigraph::degrees() const {
  std::vector<int> d(n, 0);
  for (const Edge& e : edges) {
    ++d[e.u];
    ++d[e.v];
  }
  return d;
}

std::vector<std::vector<int>> Multigraph::incidence() const {
  std::vector<std::vector<int>> inc(n);
  for (int i = 0; i < m(); ++i) {
    inc[edges[i].u].push_back(i);
    if (edges[i].v != edges[i].u) inc[edges[i].v].push_back(i);
  }
  return inc;
}

Multigraph parseGraphLine(const std::string& line, const std::string& where) {
  std::istringstream is(line);
  long n = -1, m = -1;
  if (!(is >> n >> m) || n < 1 || m < 0)
    throw InputError(where + ": expected 'n m u1-v1 ...' with n >= 1 and m >= 0");
  // The analyses are dense (n x n Laplacians, their spectra): beyond this an n in the file
  // is a typo or damage, not a graph anybody can analyse here.
  constexpr long kMaxNodes = 100000;
  if (n > kMaxNodes)
    throw InputError(where + ": n = " + std::to_string(n) + " nodes is more than the " +
                     std::to_string(kMaxNodes) + " a graph-list line may have");
  Multigraph g;
  g.n = static_cast<int>(n);
  std::string tok;
  while (is >> tok) {
    const auto dash = tok.find('-');
    long u = 0, v = 0;
    std::size_t pu = 0, pv = 0;
    try {
      if (dash == std::string::npos) throw std::invalid_argument("no dash");
      u = std::stol(tok.substr(0, dash), &pu);
      v = std::stol(tok.substr(dash + 1), &pv);
    } catch (const std::exception&) {
      throw InputError(where + ": edge '" + tok + "' is not of the form u-v");
    }
    if (pu != dash || pv != tok.size() - dash - 1)
      throw InputError(where + ": edge '" + tok + "' is not of the form u-v");
    if (u < 1 || u > n || v < 1 || v > n)
      throw InputError(where + ": edge '" + tok + "' names a node outside 1.." + std::to_string(n));
    g.edges.push_back({static_cast<int>(u - 1), static_cast<int>(v - 1), 1.0});
  }
  if (g.m() != m)
    throw InputError(where + ": header says " + std::to_string(m) + " edges, line lists " +
                     std::to_string(g.m()));
  return g;
}

std::vector<ListedGraph> readGraphList(const std::string& path) {
  std::ifstream f(path);
  if (!f) throw InputError(path + ": cannot open graph list");
  std::vector<ListedGraph> out;
  std::string line;
  int ln = 0;
  while (std::getline(f, line)) {
    ++ln;
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    out.push_back({ln, parseGraphLine(line, path + ":" + std::to_string(ln))});
  }
  return out;
}

}  // namespace asf::graph
