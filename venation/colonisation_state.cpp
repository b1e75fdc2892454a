// Checkpoints of a Colonisation: save() and load() (the private state is in colonisation_impl.h).
#include <string>

#include "core/chunk_file.h"
#include "venation/colonisation_impl.h"

namespace cellform::venation {

using core::InvalidInput;

//
// Saved: everything a later step reads that cannot be recomputed. Rebuilt: the node k-d tree (its
// answers are exact with index ties, but which boxes a sector search skips, and so the cached sector
// bests, depend on its shape: it is rebuilt as the run built it), the children lists (in node
// order, as add_node makes them), the source grid (same cell size, the alive sources), the nonuniform
// Eq. 4 table and blade (from the growth steps done), the marginal growth's precomputed sources (from
// the seed; the steps done say which have been revealed), and the batch of nodes not yet merged into the
// per-source state. That per-source state (nearest node, sector bests and lune flags) is saved as it is:
// rebuilt from scratch it would equal it only up to exact distance ties.

namespace {

constexpr const char* kStateKind = "COLO";
// 2: Urquhart cells; 3: marginal growth reveals precomputed sources; 4: lazy sector modes (a state of
// version 3 loads with every source out of lazy mode: the same results, lazy mode changes only the speed);
// 5: a leaf's step inserts its nodes into the tree as one batch (older versions inserted them one by one);
// 6: the darts thrown over the quiet steps (older states load with none: their runs settle later)
constexpr std::uint32_t kStateVersion = 6;

void put_vec3s(core::ByteWriter& w, const std::vector<Vec3>& v) {
  std::vector<double> flat;
  flat.reserve(3 * v.size());
  for (const Vec3& q : v) flat.insert(flat.end(), {q.x(), q.y(), q.z()});
  w.put_vector(flat);
}
std::vector<Vec3> get_vec3s(core::ByteReader& r) {
  const std::vector<double> flat = r.get_vector<double>();
  std::vector<Vec3> v(flat.size() / 3);
  for (std::size_t i = 0; i < v.size(); ++i) v[i] = Vec3(flat[3 * i], flat[3 * i + 1], flat[3 * i + 2]);
  return v;
}
void put_vec2s(core::ByteWriter& w, const std::vector<Vec2>& v) {
  std::vector<double> flat;
  flat.reserve(2 * v.size());
  for (const Vec2& q : v) flat.insert(flat.end(), {q.x(), q.y()});
  w.put_vector(flat);
}
std::vector<Vec2> get_vec2s(core::ByteReader& r) {
  const std::vector<double> flat = r.get_vector<double>();
  std::vector<Vec2> v(flat.size() / 2);
  for (std::size_t i = 0; i < v.size(); ++i) v[i] = Vec2(flat[2 * i], flat[2 * i + 1]);
  return v;
}
void put_lists(core::ByteWriter& w, const std::vector<std::vector<Index>>& lists) {
  w.put<std::uint64_t>(lists.size());
  for (const auto& l : lists) w.put_vector(l);
}
std::vector<std::vector<Index>> get_lists(core::ByteReader& r) {
  const auto n = r.get<std::uint64_t>();
  std::vector<std::vector<Index>> lists;
  for (std::uint64_t i = 0; i < n; ++i) lists.push_back(r.get_vector<Index>());
  return lists;
}

/// Fingerprint of what the steps depend on in the parameters (not threads, max_steps, max_nodes, max_sources).
std::uint64_t params_hash(const ColonisationParams& p) {
  core::ByteWriter w;
  for (double v : {p.source_birth_distance, p.vein_birth_distance, p.kill_distance, p.node_distance, p.darts_per_area,
                   p.initial_scale, p.final_scale, p.scale_step})
    w.put(v);
  w.put(static_cast<std::int32_t>(p.type));
  w.put(static_cast<std::int32_t>(p.neighbourhood));
  w.put(static_cast<std::int32_t>(p.growth));
  for (const GrowthFunction* f : {&p.growth_x, &p.growth_y}) {
    w.put_vector(f->y);
    w.put_vector(f->rate);
  }
  w.put<std::uint64_t>(p.growth_steps);
  w.put<std::uint64_t>(p.seed);
  w.put<std::uint64_t>(p.settle_steps);
  const std::string b = w.take();
  return core::fnv1a64(b.data(), b.size());
}

std::uint64_t leaf_hash(const Leaf& l, core::ByteWriter& w) {
  w.put(static_cast<std::int32_t>(DomainKind::leaf));
  put_vec2s(w, l.outline.points);
  put_vec2s(w, {l.petiole});
  put_vec2s(w, l.initial_nodes);
  put_vec2s(w, l.initial_sources);
  const std::string b = w.take();
  return core::fnv1a64(b.data(), b.size());
}

/// Fingerprint of the source domain (a leaf hashes the same whether given as Leaf or as Domain).
std::uint64_t domain_hash(const Domain& d) {
  core::ByteWriter w;
  if (d.kind == DomainKind::leaf) return leaf_hash(d.leaf, w);
  w.put(static_cast<std::int32_t>(d.kind));
  put_vec3s(w, {d.box_min, d.box_max, d.centre});
  w.put(d.radius);
  put_vec3s(w, d.mesh.vertices);
  std::vector<Index> tri;
  for (const auto& t : d.mesh.triangles) tri.insert(tri.end(), t.begin(), t.end());
  w.put_vector(tri);
  put_vec3s(w, d.initial_nodes);
  put_vec3s(w, d.initial_sources);
  const std::string b = w.take();
  return core::fnv1a64(b.data(), b.size());
}

void put_report(core::ByteWriter& w, const ColonisationReport& r) {
  for (std::size_t v : {r.steps, r.nodes, r.sources, r.sources_born, r.sources_removed, r.darts, r.loops})
    w.put<std::uint64_t>(v);
  w.put(r.scale);
  for (bool b : {r.finished, r.stalled, r.hit_max_steps, r.hit_max_nodes}) w.put<std::uint8_t>(b ? 1 : 0);
}
ColonisationReport get_report(core::ByteReader& r) {
  ColonisationReport rep;
  for (std::size_t* v :
       {&rep.steps, &rep.nodes, &rep.sources, &rep.sources_born, &rep.sources_removed, &rep.darts, &rep.loops})
    *v = static_cast<std::size_t>(r.get<std::uint64_t>());
  rep.scale = r.get<double>();
  for (bool* b : {&rep.finished, &rep.stalled, &rep.hit_max_steps, &rep.hit_max_nodes}) *b = r.get<std::uint8_t>() != 0;
  return rep;
}

}  // namespace

std::string Colonisation::save() const {
  const Impl& m = *impl_;
  core::ByteWriter setup;
  setup.put(params_hash(m.p));
  core::ByteWriter scratch;
  setup.put(m.region ? domain_hash(m.region->domain()) : leaf_hash(m.leaf, scratch));

  core::ByteWriter w;
  put_vec3s(w, m.nodes.points());
  w.put_vector(m.parent);
  w.put_vector(m.birth);
  std::vector<Index> ana;
  for (const auto& [a, b] : m.anastomoses) ana.insert(ana.end(), {a, b});
  w.put_vector(ana);
  put_vec3s(w, m.src);
  w.put_vector(m.alive);
  w.put_vector(m.tagged);
  w.put_vector(m.active);
  w.put_vector(m.near);
  w.put_vector(m.near_d2);
  put_lists(w, m.tags);
  put_lists(w, m.reached);
  std::vector<Index> best;
  std::vector<double> d2;
  std::vector<char> flags;  // six lune flags, then ready
  for (const Impl::Sectors& st : m.sectors) {
    best.insert(best.end(), st.best, st.best + 6);
    d2.insert(d2.end(), st.d2, st.d2 + 6);
    for (bool b : st.blocked) flags.push_back(b ? 1 : 0);
    flags.push_back(st.ready ? 1 : 0);
  }
  w.put_vector(best);
  w.put_vector(d2);
  w.put_vector(flags);
  {  // Urquhart cells: per source ready, window, r2max, vertex count, then vertices and labels; outs
    std::vector<char> ready;
    std::vector<double> num;  // window, r2max per source; x, y per vertex
    std::vector<std::int64_t> labels;
    std::vector<Index> counts;
    std::vector<std::vector<Index>> outs;
    for (const Impl::Urquhart& u : m.urq) {
      ready.push_back(u.ready ? 1 : 0);
      num.insert(num.end(), {u.window, u.cell.r2max});
      counts.push_back(static_cast<Index>(u.cell.poly.size()));
      outs.push_back(u.out);
    }
    for (const Impl::Urquhart& u : m.urq)
      for (const VoronoiCell::Vertex& v : u.cell.poly) {
        num.insert(num.end(), {v.x, v.y});
        labels.push_back(v.label);
      }
    w.put_vector(ready);
    w.put_vector(num);
    w.put_vector(labels);
    w.put_vector(counts);
    put_lists(w, outs);
  }
  w.put(m.grid.cell());
  w.put_string(m.rng.state());
  w.put(m.sigma);
  w.put<std::uint64_t>(m.grown);
  put_vec2s(w, m.node_mat);
  put_vec2s(w, m.src_mat);
  w.put<std::uint64_t>(m.quiet);
  w.put<Index>(m.synced);
  put_report(w, m.rep);
  {  // lazy sector modes: per source flag, backoff, retry step, anchor, slack; then the last segment length
    std::vector<char> lazy;
    std::vector<std::uint8_t> backoff;
    std::vector<std::uint32_t> retry;
    std::vector<Index> anchor;
    std::vector<double> slack;
    for (const Impl::Sectors& st : m.sectors) {
      lazy.push_back(st.lazy ? 1 : 0);
      backoff.push_back(st.backoff);
      retry.push_back(st.retry);
      anchor.push_back(st.anchor);
      slack.push_back(st.slack);
    }
    w.put_vector(lazy);
    w.put_vector(backoff);
    w.put_vector(retry);
    w.put_vector(anchor);
    w.put_vector(slack);
    w.put(m.last_D);
  }
  w.put<std::uint64_t>(m.quiet_darts);
  return core::write_chunk_file(kStateKind, kStateVersion, {{"setup", setup.take()}, {"state", w.take()}});
}

void Colonisation::restore(const std::string& bytes, const std::string& what) {
  Impl& m = *impl_;
  const core::ChunkFile f = core::read_chunk_file(bytes, kStateKind, kStateVersion, what);
  if (f.version < 2)  // the state chunk gained the Urquhart cells: an older layout cannot be read
    throw core::FileError(what + " has format version " + std::to_string(f.version) +
                          ", written by an older cellform whose colonisation state this one cannot continue; run the "
                          "script again");
  if (f.version < 3 && m.marginal)
    throw core::FileError(what + " has format version " + std::to_string(f.version) +
                          ": it grew a marginally growing leaf with darts over the whole blade, which this cellform "
                          "no longer does (it reveals precomputed sources at the margin); run the script again");
  {
    core::ByteReader r(f.at("setup", what), what);
    const auto ph = r.get<std::uint64_t>(), dh = r.get<std::uint64_t>();
    if (ph != params_hash(m.p))
      throw ParametersChanged(what + " was saved with other colonisation parameters (or another seed): only " +
                              kContinueMayDiffer);
    core::ByteWriter scratch;
    if (dh != (m.region ? domain_hash(m.region->domain()) : leaf_hash(m.leaf, scratch)))
      throw DomainChanged(what +
                          " was saved for another source domain (leaf, volume or surface): the outline or mesh "
                          "files changed since, or the cellform that saved it made its outlines or cell surface "
                          "differently (a toothed outline, an outline file's scale, a sheet's orientation); continue "
                          "it with the files and the cellform it was grown with");
  }
  core::ByteReader r(f.at("state", what), what);
  const std::vector<Vec3> points = get_vec3s(r);
  m.parent = r.get_vector<Index>();
  m.birth = r.get_vector<std::uint32_t>();
  const std::vector<Index> ana = r.get_vector<Index>();
  m.src = get_vec3s(r);
  m.alive = r.get_vector<char>();
  m.tagged = r.get_vector<char>();
  m.active = r.get_vector<Index>();
  m.near = r.get_vector<Index>();
  m.near_d2 = r.get_vector<double>();
  m.tags = get_lists(r);
  m.reached = get_lists(r);
  const std::vector<Index> best = r.get_vector<Index>();
  const std::vector<double> d2 = r.get_vector<double>();
  const std::vector<char> flags = r.get_vector<char>();
  const std::vector<char> u_ready = r.get_vector<char>();
  const std::vector<double> u_num = r.get_vector<double>();
  const std::vector<std::int64_t> u_labels = r.get_vector<std::int64_t>();
  const std::vector<Index> u_counts = r.get_vector<Index>();
  const std::vector<std::vector<Index>> u_outs = get_lists(r);
  const double cell = r.get<double>();
  const std::string rng = r.get_string();
  m.sigma = r.get<double>();
  m.grown = static_cast<std::size_t>(r.get<std::uint64_t>());
  m.node_mat = get_vec2s(r);
  m.src_mat = get_vec2s(r);
  m.quiet = static_cast<std::size_t>(r.get<std::uint64_t>());
  m.synced = r.get<Index>();
  m.rep = get_report(r);
  m.rep.marginal_darts = m.precomputed.darts;  // made again with the simulation, not saved
  std::vector<char> lazy;
  std::vector<std::uint8_t> backoff;
  std::vector<std::uint32_t> retry;
  std::vector<Index> anchor;
  std::vector<double> slack;
  m.last_D = 0;
  if (f.version >= 4) {
    lazy = r.get_vector<char>();
    backoff = r.get_vector<std::uint8_t>();
    retry = r.get_vector<std::uint32_t>();
    anchor = r.get_vector<Index>();
    slack = r.get_vector<double>();
    m.last_D = r.get<double>();
  }
  m.quiet_darts = f.version >= 6 ? static_cast<std::size_t>(r.get<std::uint64_t>()) : 0;

  // consistency: sizes and indices (the checksum catches damage; this catches a state of another build)
  const std::size_t n = points.size(), ns = m.src.size();
  const bool closed = m.p.type == VenationType::closed;
  bool ok =
      r.done() && n > 0 && m.parent.size() == n && m.birth.size() == n && ana.size() % 2 == 0 && m.alive.size() == ns &&
      m.tagged.size() == ns && m.near.size() == ns && m.near_d2.size() == ns && m.tags.size() == (closed ? ns : 0) &&
      m.reached.size() == (closed ? ns : 0) && best.size() == 6 * ns && d2.size() == 6 * ns && flags.size() == 7 * ns &&
      m.synced <= n && m.rep.nodes == n &&
      (m.nonuniform ? m.node_mat.size() == n && m.src_mat.size() == ns : m.node_mat.empty() && m.src_mat.empty()) &&
      cell > 0 && m.sigma > 0;
  for (Index i = 0; ok && i < n; ++i)
    ok = (m.parent[i] == kNoIndex || m.parent[i] < i) && (i == 0 || m.birth[i] >= m.birth[i - 1]) &&
         points[i].allFinite();
  for (std::size_t s = 0; ok && s < ns; ++s) ok = m.src[s].allFinite() && !std::isnan(m.near_d2[s]);
  for (std::size_t k = 0; ok && k < d2.size(); ++k) ok = !std::isnan(d2[k]);
  ok = ok && std::isfinite(cell) && std::isfinite(m.sigma);
  for (const auto* mats : {&m.node_mat, &m.src_mat})  // nonuniform growth: positions come from these
    for (std::size_t k = 0; ok && k < mats->size(); ++k) ok = (*mats)[k].allFinite();
  for (std::size_t k = 0; ok && k < u_num.size(); ++k) ok = std::isfinite(u_num[k]);
  for (Index v : ana) ok = ok && v < n;
  for (Index v : best) ok = ok && (v == kNoIndex || v < n);
  const std::size_t nu = m.urquhart() ? ns : 0;
  std::size_t vertices = 0;
  for (Index c : u_counts) vertices += c;
  ok = ok && u_ready.size() == nu && u_counts.size() == nu && u_outs.size() == nu &&
       u_num.size() == 2 * nu + 2 * vertices && u_labels.size() == vertices;
  for (std::int64_t l : u_labels) ok = ok && l >= -1 && l < static_cast<std::int64_t>(n);
  for (const auto& l : u_outs)
    for (Index v : l) ok = ok && v < n;
  for (Index v : m.near) ok = ok && (v == kNoIndex || v < n);
  if (f.version >= 4) {
    ok = ok && lazy.size() == ns && backoff.size() == ns && retry.size() == ns && anchor.size() == ns &&
         slack.size() == ns && std::isfinite(m.last_D) && m.last_D >= 0;
    for (std::size_t s = 0; ok && s < ns; ++s)
      ok = !lazy[s] || (anchor[s] < n && std::isfinite(slack[s]) && m.p.type == VenationType::closed && !m.nonuniform);
  }
  for (std::size_t a = 0; ok && a < m.active.size(); ++a)
    ok = m.active[a] < ns && m.alive[m.active[a]] && (a == 0 || m.active[a] > m.active[a - 1]);
  for (const auto* lists : {&m.tags, &m.reached})
    for (const auto& l : *lists)
      for (Index v : l) ok = ok && v < n;
  if (ok) ok = m.rng.set_state(rng);
  if (!ok)
    throw core::FileError(what + " is corrupt (inconsistent colonisation state, or a position that is no number)");

  // the k-d tree as the run built it (its shape decides which boxes the sector searches skip, and so
  // the per-source sector bests, though not the neighbourhoods): nonuniform growth rebuilt it from all
  // nodes at its last growth step (at the end of step `grown`); every other node was inserted, the
  // initial ones and those of 3-D runs (and of any run saved before version 5) one by one, those of a
  // leaf's step in one batch
  m.nodes.clear();
  m.witness.clear();  // laid out again from all nodes by the next darts
  std::size_t built = 0;
  if (m.nonuniform && m.grown > 0)
    while (built < n && m.birth[built] <= m.grown) ++built;
  m.nodes.assign(std::span<const Vec3>(points).first(built));
  for (std::size_t i = built; i < n;) {
    std::size_t j = i + 1;
    if (!m.region && m.birth[i] > 0 && f.version >= 5)
      while (j < n && m.birth[j] == m.birth[i]) ++j;
    m.nodes.insert_batch(std::span<const Vec3>(points).subspan(i, j - i));
    i = j;
  }
  m.first_child.assign(n, kNoIndex);
  m.next_sibling.assign(n, kNoIndex);
  for (Index i = 0; i < n; ++i)
    if (m.parent[i] != kNoIndex) {
      m.next_sibling[i] = m.first_child[m.parent[i]];
      m.first_child[m.parent[i]] = i;
    }
  m.anastomoses.clear();
  m.loop_keys.clear();
  for (std::size_t i = 0; i < ana.size(); i += 2) {
    m.anastomoses.emplace_back(ana[i], ana[i + 1]);
    m.loop_keys.insert(Impl::loop_key(ana[i], ana[i + 1]));
  }
  m.sectors.assign(ns, {});
  for (std::size_t s = 0; s < ns; ++s) {
    Impl::Sectors& st = m.sectors[s];
    for (int k = 0; k < 6; ++k) {
      st.best[k] = best[6 * s + k];
      st.d2[k] = d2[6 * s + k];
      st.blocked[k] = flags[7 * s + k] != 0;
    }
    st.ready = flags[7 * s + 6] != 0;
    if (f.version >= 4) {
      st.lazy = lazy[s] != 0;
      st.backoff = backoff[s];
      st.retry = retry[s];
      st.anchor = anchor[s];
      st.slack = slack[s];
    }
  }
  m.urq.assign(nu, {});
  for (std::size_t s = 0, at = 2 * nu, lab = 0; s < nu; ++s) {
    Impl::Urquhart& u = m.urq[s];
    u.ready = u_ready[s] != 0;
    u.window = u_num[2 * s];
    u.cell.r2max = u_num[2 * s + 1];
    for (Index k = 0; k < u_counts[s]; ++k, at += 2) u.cell.poly.push_back({u_num[at], u_num[at + 1], u_labels[lab++]});
    u.out = u_outs[s];
  }
  m.grid.reset(cell);
  for (Index s : m.active) m.grid.insert(s, m.src[s]);
  if (m.nonuniform) m.make_table();
  m.fresh_first = m.fresh_last = kNoIndex;  // forces sync_fresh to index [synced, n)
  m.sync_fresh();
  m.per_source.clear();
  m.child.clear();
  m.acc.clear();
  // the limits are those of `params`
  m.rep.hit_max_steps = m.rep.steps >= m.p.max_steps && !m.rep.finished && !m.rep.stalled;
  m.rep.hit_max_nodes = n >= m.p.max_nodes && !m.rep.finished && !m.rep.stalled;
  m.rep.hit_max_sources = m.active.size() >= m.p.max_sources && !m.rep.finished && !m.rep.stalled;
}

Colonisation Colonisation::load(const Domain& domain, const ColonisationParams& params, const std::string& bytes,
                                const std::string& what) {
  Colonisation c(domain, params);
  c.restore(bytes, what);
  return c;
}

Colonisation Colonisation::load(const Leaf& leaf, const ColonisationParams& params, const std::string& bytes,
                                const std::string& what) {
  Colonisation c(leaf, params);
  c.restore(bytes, what);
  return c;
}

}  // namespace cellform::venation
