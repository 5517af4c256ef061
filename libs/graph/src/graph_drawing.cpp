// Edge weights drawn on a graph (thesis figs. 5.11-5.13) and a deterministic layout for
// graphs that come without positions.
#include <asf/atomic_file.h>
#include <asf/errors.h>
#include <asf/graph/drawing.h>
#include <asf/text.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <queue>
#include <sstream>

namespace asf::graph {

namespace {

using Eigen::MatrixXd;
using Eigen::Vector2d;

// Hop distances between every pair (BFS from each node); unreachable pairs get -1.
MatrixXd hopDistances(const Multigraph& g) {
  const auto inc = g.incidence();
  MatrixXd D = MatrixXd::Constant(g.n, g.n, -1);
  for (int s = 0; s < g.n; ++s) {
    std::queue<int> q;
    D(s, s) = 0;
    q.push(s);
    while (!q.empty()) {
      const int a = q.front();
      q.pop();
      for (int j : inc[a]) {
        const int b = g.edges[j].u == a ? g.edges[j].v : g.edges[j].u;
        if (D(s, b) < 0) {
          D(s, b) = D(s, a) + 1;
          q.push(b);
        }
      }
    }
  }
  const double far = D.maxCoeff() + 1;
  for (int i = 0; i < g.n; ++i)
    for (int j = 0; j < g.n; ++j)
      if (D(i, j) < 0) D(i, j) = far;
  return D;
}

// Classical MDS: the two leading eigenvectors of -J D^2 J / 2, scaled.
MatrixXd classicalMds(const MatrixXd& D) {
  const auto n = D.rows();
  MatrixXd B = -0.5 * D.cwiseAbs2();
  B.rowwise() -= B.colwise().mean();
  B.colwise() -= B.rowwise().mean();
  Eigen::SelfAdjointEigenSolver<MatrixXd> es(B);
  MatrixXd X(n, 2);
  for (int c = 0; c < 2; ++c) {
    const double lam = std::max(0.0, es.eigenvalues()[n - 1 - c]);
    X.col(c) = es.eigenvectors().col(n - 1 - c) * std::sqrt(lam);
  }
  return X;
}

}  // namespace

std::vector<Vector2d> stressLayout(const Multigraph& g, int iterations) {
  std::vector<Vector2d> out(std::max(0, g.n), Vector2d::Zero());
  if (g.n <= 1) return out;
  const int n = g.n;
  const MatrixXd D = hopDistances(g);
  MatrixXd X = classicalMds(D);
  // A path or a tree can leave the second MDS axis empty: spread it a little, deterministically.
  for (int i = 0; i < n; ++i) X(i, 1) += 1e-3 * std::sin(1.0 + i);
  MatrixXd W = MatrixXd::Zero(n, n), Lw = MatrixXd::Zero(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      if (i != j) {
        W(i, j) = 1.0 / (D(i, j) * D(i, j));
        Lw(i, j) = -W(i, j);
        Lw(i, i) += W(i, j);
      }
  // Lw is singular along 1; the update is centred, so solve with Lw + 11^T / n.
  const Eigen::LDLT<MatrixXd> solver(Lw + MatrixXd::Constant(n, n, 1.0 / n));
  MatrixXd Lx(n, n);
  for (int it = 0; it < iterations; ++it) {
    Lx.setZero();
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        if (i == j) continue;
        const double dist = (X.row(i) - X.row(j)).norm();
        if (dist < 1e-12) continue;
        Lx(i, j) = -W(i, j) * D(i, j) / dist;
        Lx(i, i) -= Lx(i, j);
      }
    MatrixXd Xn = solver.solve(Lx * X);
    Xn.rowwise() -= Xn.colwise().mean();
    const double change = (Xn - X).norm();
    X = Xn;
    if (change < 1e-9 * (1 + X.norm())) break;
  }
  for (int i = 0; i < n; ++i) out[i] = X.row(i).transpose();
  return out;
}

void writeWeightsSvg(const Multigraph& g, const std::vector<Vector2d>& positions,
                     const std::vector<WeightPanel>& panels, const std::string& title,
                     const std::string& path) {
  if (static_cast<int>(positions.size()) != g.n)
    throw InputError("writeWeightsSvg: " + std::to_string(positions.size()) + " positions for " +
                     std::to_string(g.n) + " nodes");
  for (const auto& p : panels)
    if (p.weights.size() != g.m())
      throw InputError("writeWeightsSvg: panel '" + p.title + "' has " +
                       std::to_string(p.weights.size()) + " weights for " + std::to_string(g.m()) +
                       " edges");
  Vector2d lo = Vector2d::Constant(1e300), hi = Vector2d::Constant(-1e300);
  for (const auto& q : positions) {
    lo = lo.cwiseMin(q);
    hi = hi.cwiseMax(q);
  }
  if (positions.empty()) lo = hi = Vector2d::Zero();
  const double side = 360, margin = 24, header = 40;
  const double span = std::max({hi.x() - lo.x(), hi.y() - lo.y(), 1e-9});
  const double scale = (side - 2 * margin) / span;
  const double width = side * std::max<std::size_t>(1, panels.size()), height = side + header;
  std::ostringstream s;
  s << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << width << "\" height=\"" << height
    << "\" viewBox=\"0 0 " << width << " " << height << "\" font-family=\"sans-serif\">\n"
    << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
    << "<text x=\"" << width / 2 << "\" y=\"16\" text-anchor=\"middle\" font-size=\"13\">"
    << htmlEscape(title) << "</text>\n";
  // Map y up (poses) to SVG y down; centre the drawing in its panel.
  const Vector2d mid = 0.5 * (lo + hi);
  auto px = [&](std::size_t panel, const Vector2d& q) {
    return Vector2d(side * panel + side / 2 + scale * (q.x() - mid.x()),
                    header + side / 2 - scale * (q.y() - mid.y()));
  };
  for (std::size_t k = 0; k < panels.size(); ++k) {
    const auto& p = panels[k];
    const double wmax = p.weights.size() ? p.weights.maxCoeff() : 0;
    s << "<g>\n<text x=\"" << side * k + side / 2 << "\" y=\"34\" text-anchor=\"middle\" "
      << "font-size=\"12\">" << htmlEscape(p.title) << "</text>\n";
    for (int j = 0; j < g.m(); ++j) {
      const auto& e = g.edges[j];
      if (e.u == e.v) continue;
      const Vector2d a = px(k, positions[e.u]), b = px(k, positions[e.v]);
      const double w = wmax > 0 ? 8.0 * p.weights[j] / wmax : 0;
      s << "<line x1=\"" << formatFixed(a.x(), 2) << "\" y1=\"" << formatFixed(a.y(), 2)
        << "\" x2=\"" << formatFixed(b.x(), 2) << "\" y2=\"" << formatFixed(b.y(), 2)
        << "\" stroke=\"#0072B2\" stroke-linecap=\"round\" ";
      if (w > 0.05)
        s << "stroke-width=\"" << formatFixed(w, 2) << "\"";
      else
        s << "stroke-width=\"0.5\" stroke-dasharray=\"2,2\"";
      s << "><title>edge " << j + 1 << " (" << e.u + 1 << "-" << e.v + 1 << "): " << p.weights[j]
        << "</title></line>\n";
    }
    const double r = g.n > 200 ? 0.8 : 2.5;
    for (int i = 0; i < g.n; ++i) {
      const Vector2d c = px(k, positions[i]);
      s << "<circle cx=\"" << formatFixed(c.x(), 2) << "\" cy=\"" << formatFixed(c.y(), 2)
        << "\" r=\"" << r << "\" fill=\"#D55E00\"/>\n";
    }
    s << "</g>\n";
  }
  s << "</svg>\n";
  writeFileAtomically(path, s.str(), "drawing");
}

}  // namespace asf::graph
