// g2o 2D text format, read and written with line-precise errors.
#include <asf/atomic_file.h>
#include <asf/errors.h>
#include <asf/pose_graph.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <map>
#include <set>
#include <sstream>

namespace asf {

namespace {

/// The records of a g2o text, checked line by line (errors name the file and line).
class G2oRecords {
 public:
  struct RawEdge {
    long from, to;
    PoseEdge e;
    int line;
  };
  explicit G2oRecords(const std::string& name) : name_(name) {}

  void parse(const std::string& text) {
    std::istringstream is(text);
    std::string line;
    while (std::getline(is, line)) {
      ++n_;
      std::istringstream ls(line);
      std::string tag;
      if (!(ls >> tag) || tag[0] == '#') continue;
      if (tag == "VERTEX_SE2")
        vertex(ls);
      else if (tag == "EDGE_SE2")
        edge(ls);
      else if (tag == "FIX")
        fix(ls);
      else
        fail("unknown record '" + tag + "' (expected VERTEX_SE2, EDGE_SE2 or FIX)");
    }
  }

  std::map<long, mrpt::poses::CPose2D> vertices;
  std::vector<RawEdge> raw;
  std::vector<std::pair<long, int>> fixes;  ///< id, line

 private:
  [[noreturn]] void fail(const std::string& why) const {
    throw InputError(name_ + ":" + std::to_string(n_) + ": " + why);
  }
  // Anything after a record's values but a comment means the line is not what we think.
  void requireEnd(std::istringstream& ls, const std::string& record) const {
    std::string extra;
    if (ls >> extra && extra[0] != '#')
      fail("malformed " + record + ": unexpected '" + extra + "' after its values");
  }

  void vertex(std::istringstream& ls) {
    long id;
    double x, y, th;
    if (!(ls >> id >> x >> y >> th)) fail("malformed VERTEX_SE2 (expected: id x y theta)");
    requireEnd(ls, "VERTEX_SE2");
    if (id < 0) fail("negative vertex id");
    if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(th))
      fail("vertex " + std::to_string(id) + " has a non-finite pose");
    if (vertices.count(id))
      fail("vertex " + std::to_string(id) + " defined twice (first at line " +
           std::to_string(vertex_line_[id]) + ")");
    vertices[id] = mrpt::poses::CPose2D(x, y, th);
    vertex_line_[id] = n_;
  }

  void edge(std::istringstream& ls) {
    RawEdge r;
    double dx, dy, dth, i11, i12, i13, i22, i23, i33;
    if (!(ls >> r.from >> r.to >> dx >> dy >> dth >> i11 >> i12 >> i13 >> i22 >> i23 >> i33))
      fail("malformed EDGE_SE2 (expected: from to dx dy dtheta I11 I12 I13 I22 I23 I33)");
    requireEnd(ls, "EDGE_SE2");
    const std::string which = std::to_string(r.from) + " -> " + std::to_string(r.to);
    if (r.from == r.to)  // it constrains nothing; an optimizer would report it "converged"
      fail("edge " + which + " joins a vertex to itself");
    if (!std::isfinite(dx) || !std::isfinite(dy) || !std::isfinite(dth))
      fail("edge " + which + " has a non-finite measurement");
    Eigen::Matrix3d I;
    I << i11, i12, i13, i12, i22, i23, i13, i23, i33;
    if (!I.allFinite()) fail("information matrix of edge " + which + " is not finite");
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(I);
    if (es.eigenvalues().minCoeff() <= 0)
      fail("information matrix of edge " + which + " is not positive definite");
    r.e.mean = mrpt::poses::CPose2D(dx, dy, dth);
    r.e.information = I;
    r.e.kind = std::abs(r.to - r.from) == 1 ? EdgeKind::Odometry : EdgeKind::LoopClosure;
    r.line = n_;
    raw.push_back(r);
  }

  void fix(std::istringstream& ls) {
    long id;
    int count = 0;
    while (ls >> id) {
      fixes.emplace_back(id, n_);
      ++count;
    }
    if (!ls.eof()) {  // stopped on something that is not an id
      ls.clear();
      std::string extra;
      ls >> extra;
      if (extra[0] != '#') fail("malformed FIX: '" + extra + "' is not a vertex id");
    }
    if (count == 0) fail("malformed FIX (expected: FIX id [id ...])");
  }

  const std::string& name_;
  int n_ = 0;  ///< the line being read
  std::map<long, int> vertex_line_;
};

/// The nodes: the vertices (ids 0..n-1), or for an edge-only file the composed odometry chain.
void addNodes(const G2oRecords& rec, const std::string& name, PoseGraph& g) {
  if (!rec.vertices.empty()) {
    const long max_id = rec.vertices.rbegin()->first;
    for (long i = 0; i <= max_id; ++i)
      if (!rec.vertices.count(i))
        throw InputError(name + ": vertex ids must be 0..n-1; vertex " + std::to_string(i) +
                         " is missing");
    for (const auto& [id, p] : rec.vertices) g.addNode(p);
    return;
  }
  if (rec.raw.empty()) return;
  long max_id = -1;
  for (const auto& r : rec.raw) max_id = std::max({max_id, r.from, r.to});
  // Edge-only file: initial guess by composing the odometry chain i -> i+1.
  std::map<long, const PoseEdge*> chain;
  for (const auto& r : rec.raw)
    if (r.to == r.from + 1 && !chain.count(r.from)) chain[r.from] = &r.e;
  g.addNode(mrpt::poses::CPose2D());
  for (long i = 1; i <= max_id; ++i) {
    auto it = chain.find(i - 1);
    if (it == chain.end())
      throw InputError(name + ": no VERTEX lines and no odometry edge " + std::to_string(i - 1) +
                       " -> " + std::to_string(i) + " to compose an initial guess");
    g.addNode(g.nodes.back().pose + it->second->mean);
  }
}

}  // namespace

PoseGraph parseG2o(const std::string& text, const std::string& name) {
  G2oRecords rec(name);
  rec.parse(text);
  PoseGraph g;
  addNodes(rec, name, g);
  for (const auto& r : rec.raw) {
    if (r.from < 0 || r.to < 0 || r.from >= static_cast<long>(g.nodes.size()) ||
        r.to >= static_cast<long>(g.nodes.size()))
      throw InputError(name + ":" + std::to_string(r.line) + ": edge " + std::to_string(r.from) +
                       " -> " + std::to_string(r.to) + " names an undefined vertex");
    PoseEdge e = r.e;
    e.from = static_cast<NodeId>(r.from);
    e.to = static_cast<NodeId>(r.to);
    g.edges.push_back(e);
  }
  for (const auto& [id, l] : rec.fixes) {
    if (id < 0 || id >= static_cast<long>(g.nodes.size()))
      throw InputError(name + ":" + std::to_string(l) + ": FIX names undefined vertex " +
                       std::to_string(id));
    g.fixed.push_back(static_cast<NodeId>(id));
  }
  return g;
}

PoseGraph readG2o(const std::string& path) {
  std::ifstream f(path);
  if (!f) throw InputError(path + ": cannot open");
  std::stringstream ss;
  ss << f.rdbuf();
  return parseG2o(ss.str(), path);
}

std::string formatG2o(const PoseGraph& g) {
  std::ostringstream os;
  os << std::setprecision(17);
  for (const auto& n : g.nodes)
    os << "VERTEX_SE2 " << n.id << ' ' << n.pose.x() << ' ' << n.pose.y() << ' ' << n.pose.phi()
       << '\n';
  for (const auto& e : g.edges) {
    const auto& I = e.information;
    os << "EDGE_SE2 " << e.from << ' ' << e.to << ' ' << e.mean.x() << ' ' << e.mean.y() << ' '
       << e.mean.phi() << ' ' << I(0, 0) << ' ' << I(0, 1) << ' ' << I(0, 2) << ' ' << I(1, 1)
       << ' ' << I(1, 2) << ' ' << I(2, 2) << '\n';
  }
  for (auto id : g.fixed) os << "FIX " << id << '\n';
  return os.str();
}

void writeG2o(const PoseGraph& g, const std::string& path) {
  // Through a temporary file and a rename: a crash never leaves a half-written graph.
  writeFileAtomically(path, formatG2o(g), "graph");
}

}  // namespace asf
