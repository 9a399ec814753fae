// Position coding details the round-trip tests do not pin: isolated vertices chained through
// near neighbours (cheap, within the bound, in order when asked), predictor 4's pull
// towards the neighbours' centroid (exact arithmetic, chosen where it pays, round trips) and
// predictor 5's coded choice among the parallelograms (round trips, pays on a noisy surface).

#include "compress/meshes.h"

#include <geom/compress/container/codec.h>
#include <geom/compress/container/mesh_tables.h>
#include <geom/compress/point_chain.h>
#include <geom/compress/predict.h>
#include <geom/compress/quantise.h>
#include <geom/core/validate.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <utility>

namespace geom::codec::detail {
namespace {

std::vector<QPoint> shuffled_line(unsigned n, unsigned seed) {
  std::vector<QPoint> q;
  for (std::uint32_t i = 0; i < n; ++i) q.push_back({5 * i, 7, 3 * i});
  std::shuffle(q.begin(), q.end(), std::mt19937(seed));
  return q;
}

// The readers take whole words (raw bits) and computed byte counts (rANS) away from the end
// of a stream and fall back to byte steps near it: both paths must agree with the writers
// for every width, up to the last byte, and a read past the end must throw.
TEST(EntropyReaders, AgreeWithTheWritersUpToTheLastByte) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 40; ++trial) {
    const int n = 1 + static_cast<int>(rng() % 300);
    std::vector<unsigned> width(n), symbol(n);
    std::vector<std::uint32_t> value(n);
    BitWriter bw;
    RansEncoder re;
    AdaptiveModel enc_model(13);
    for (int i = 0; i < n; ++i) {
      width[i] = rng() % 33;
      value[i] = width[i] == 32 ? rng() : rng() & ((1u << width[i]) - 1);
      bw.put(value[i], width[i]);
      symbol[i] = rng() % 4 == 0 ? rng() % 13 : rng() % 2;  // skewed, with rare long ones
      re.encode(enc_model, symbol[i]);
      if (width[i] <= 15) re.encode_flat(value[i] & ((1u << width[i]) - 1), width[i]);
    }
    const std::vector<std::uint8_t> raw = bw.finish(), rans = re.finish();
    BitReader br(raw, 0);
    RansDecoder rd(rans, 0);
    AdaptiveModel dec_model(13);
    for (int i = 0; i < n; ++i) {
      ASSERT_EQ(br.get(width[i]), value[i]) << "trial " << trial << " value " << i;
      ASSERT_EQ(rd.decode(dec_model), symbol[i]) << "trial " << trial << " symbol " << i;
      if (width[i] <= 15) {
        ASSERT_EQ(rd.decode_flat(width[i]), value[i] & ((1u << width[i]) - 1));
      }
    }
    rd.finish();
    // Whatever padding the last byte has, a full byte more is past the end.
    EXPECT_THROW(br.get(8), DecodeError);
    EXPECT_THROW(rd.decode_flat(15), DecodeError);
  }
}

// The decoders' symbol search (SSE2 compares of 16 boundaries at a time where available)
// against the definition, for every slot, every alphabet size (one, two and four groups of
// boundaries) and both model types, after enough skewed updates to move every boundary;
// then a coded round trip through the same models.
template <class Model>
void expect_find_matches_intervals(Model& model, unsigned n, const char* what) {
  std::mt19937 rng(n);
  RansEncoder re;
  std::vector<unsigned> coded;
  Model enc = model;
  for (int i = 0; i < 3000; ++i) {
    // Mostly low symbols, some of every size, and the last one now and then.
    const unsigned s = rng() % 3 == 0 ? rng() % n : (rng() % 7 == 0 ? n - 1 : rng() % 2);
    coded.push_back(s);
    re.encode(enc, s);
  }
  const std::vector<std::uint8_t> bytes = re.finish();
  RansDecoder rd(bytes, 0);
  for (std::size_t i = 0; i < coded.size(); ++i) {
    ASSERT_EQ(rd.decode(model), coded[i]) << what << " n " << n << " symbol " << i;
    if (i % 1000 != 999) continue;
    for (std::uint32_t slot = 0; slot < kProbScale; ++slot) {
      const unsigned s = model.find(slot);
      ASSERT_LT(s, n) << what << " n " << n << " slot " << slot;
      ASSERT_TRUE(model.start(s) <= slot && slot < model.start(s) + model.freq(s))
          << what << " n " << n << " slot " << slot << " found " << s;
    }
  }
  rd.finish();
}

TEST(EntropyModels, FindTheSymbolOfEverySlotForEveryAlphabet) {
  for (unsigned n = 2; n <= kMaxSymbols; ++n) {
    AdaptiveModel model(n);
    expect_find_matches_intervals(model, n, "AdaptiveModel");
  }
  auto small = [](auto model) { expect_find_matches_intervals(model, model.size(), "SmallModel"); };
  small(SmallModel<2>{});
  small(SmallModel<3>{});
  small(SmallModel<4>{});
  small(SmallModel<5>{});
  small(SmallModel<6>{});
  small(SmallModel<7>{});
  small(SmallModel<8>{});
  small(TinyModel{2});
  small(TinyModel{4});
}

// The residual tops' models (TinyModel) must code exactly as the SmallModels of their size
// that the format names, and their one-symbol form must cost nothing: anywhere, and up to
// the stream's last byte.
TEST(EntropyModels, TinyModelCodesAsSmallModelAndItsCertainSymbolReadsNothing) {
  // The certain symbol (one-symbol model) is coded too, since each symbol takes its turn on
  // the rANS lanes; it adds no byte.
  std::mt19937 rng(11);
  RansEncoder by_small, by_tiny, without_certain;
  SmallModel<2> small2, plain2;
  SmallModel<4> small4, plain4;
  TinyModel tiny2(2), tiny4(4), certain_small(1), certain_tiny(1);
  std::vector<std::pair<bool, unsigned>> coded;  // (four symbols, symbol)
  for (int i = 0; i < 5000; ++i) {
    const bool four = rng() % 3 != 0;
    const unsigned s = rng() % 4 == 0 ? rng() % (four ? 4 : 2) : 0;  // skewed
    coded.emplace_back(four, s);
    by_small.encode(certain_small, 0);
    four ? by_small.encode(small4, s) : by_small.encode(small2, s);
    by_tiny.encode(certain_tiny, 0);
    by_tiny.encode(four ? tiny4 : tiny2, s);
    four ? without_certain.encode(plain4, s) : without_certain.encode(plain2, s);
    // Two certain symbols in a row keep the next symbol on its lane.
    without_certain.encode(certain_small, 0);
    without_certain.encode(certain_small, 0);
  }
  for (int i = 0; i < 3000; ++i) by_tiny.encode(certain_tiny, 0), by_small.encode(certain_small, 0);
  const std::vector<std::uint8_t> bytes = by_tiny.finish();
  ASSERT_EQ(bytes, by_small.finish());
  RansEncoder plain;
  SmallModel<2> p2;
  SmallModel<4> p4;
  for (const auto& [four, s] : coded) four ? plain.encode(p4, s) : plain.encode(p2, s);
  EXPECT_EQ(without_certain.finish().size(), plain.finish().size());
  RansDecoder rd(bytes, 0);
  TinyModel dec2(2), dec4(4), certain(1);
  for (std::size_t i = 0; i < coded.size(); ++i) {
    ASSERT_EQ(rd.decode(certain), 0u) << i;
    ASSERT_EQ(rd.decode(coded[i].first ? dec4 : dec2), coded[i].second) << i;
  }
  for (int i = 0; i < 3000; ++i) ASSERT_EQ(rd.decode(certain), 0u);  // past rebuilds, at the end
  rd.finish();
}

TEST(EntropyModels, TwoLanesDecodeWhatTheyCodeAndOneLaneStreamsStillDecode) {
  // Symbols of several models and flat values, decoded on two lanes; and a one-lane stream
  // (as encoders before two lanes wrote them), built here by hand: one state, 4 bytes.
  std::mt19937 rng(5);
  RansEncoder re;
  AdaptiveModel m(20);
  std::vector<unsigned> sym;
  for (int i = 0; i < 20000; ++i) {
    const unsigned s = rng() % 5 == 0 ? rng() % 20 : rng() % 3;
    sym.push_back(s);
    if (i % 7 == 0) re.encode_flat(s, 5); else re.encode(m, s);
  }
  const std::vector<std::uint8_t> bytes = re.finish();
  RansDecoder rd(bytes, 0);
  AdaptiveModel d(20);
  for (int i = 0; i < 20000; ++i) ASSERT_EQ(i % 7 == 0 ? rd.decode_flat(5) : rd.decode(d), sym[i]) << i;
  rd.finish();
  // A one-lane stream of one flat 3-bit value 5: state 2^23 coded gives 2^26 + 5, no
  // renormalisation byte.
  const std::vector<std::uint8_t> one_lane{0x04, 0x00, 0x00, 0x05};
  RansDecoder old(one_lane, 0, 1);
  EXPECT_EQ(old.decode_flat(3), 5u);
  old.finish();
  EXPECT_THROW(RansDecoder(one_lane, 0, 2), DecodeError);  // two lanes need 8 bytes
  // States no encoder writes: 2^31 and above, below 2^23; and lane counts other than 1, 2.
  EXPECT_THROW(RansDecoder(std::vector<std::uint8_t>{0x80, 0, 0, 0}, 0, 1), DecodeError);
  EXPECT_THROW(RansDecoder(std::vector<std::uint8_t>{0x00, 0x7f, 0xff, 0xff}, 0, 1), DecodeError);
  EXPECT_THROW(RansDecoder(one_lane, 0, 3), InvalidArgument);
}

TEST(PointChain, WalksALineGivenInRandomOrder) {
  const std::vector<QPoint> q = shuffled_line(300, 3);
  const std::vector<std::uint32_t> chain = point_chain(q);
  ASSERT_EQ(chain.size(), q.size());
  for (std::uint32_t i = 0; i < chain.size(); ++i) EXPECT_EQ(q[chain[i]][0], 5 * i) << i;
}

TEST(PointChain, PermutesEmptyCoincidentAndHugeInput) {
  EXPECT_TRUE(point_chain({}).empty());
  EXPECT_EQ(point_chain(std::vector<QPoint>{{1, 2, 3}}), std::vector<std::uint32_t>{0});
  std::mt19937 rng(5);
  std::vector<QPoint> q(500, QPoint{9, 9, 9});
  for (std::size_t i = 0; i < q.size(); i += 3) q[i] = {std::uint32_t(rng() % (1u << 30)), std::uint32_t(rng() % (1u << 30)), (1u << 30) - 1};
  std::vector<std::uint32_t> chain = point_chain(q);
  std::sort(chain.begin(), chain.end());
  for (std::uint32_t i = 0; i < chain.size(); ++i) ASSERT_EQ(chain[i], i);
}

/// The definition in FORMAT.md, in 128-bit arithmetic throughout.
std::uint32_t blended_reference(std::int64_t s, std::int64_t e, unsigned count, unsigned k,
                                std::uint32_t top) {
  __extension__ typedef __int128 Wide;
  const Wide num = 2 * Wide(16 - k) * s + Wide(k) * e, den = Wide(32) * count;
  const Wide a = 2 * num + den, b = 2 * den;
  Wide m = a / b;
  if (a % b != 0 && a < 0) --m;
  return static_cast<std::uint32_t>(std::clamp<Wide>(m, 0, top));
}

TEST(BlendedMean, MatchesTheDefinitionOnBothArithmeticPaths) {
  const std::uint32_t top = (1u << 30) - 1;
  EXPECT_EQ(blended_mean(2 * 7, 0, 2, 0, top), 7u);   // k = 0: the parallelograms' mean
  EXPECT_EQ(blended_mean(10, 2 * 40, 1, 8, top), 25u);  // halfway to the edge midpoint 40
  EXPECT_EQ(blended_mean(-9, 0, 1, 1, top), 0u);        // clamped below
  EXPECT_EQ(blended_mean(3, 4, 1, 15, top), 2u);        // 3·1/16 + 2·15/16 = 2.06
  std::mt19937_64 rng(17);
  for (int trial = 0; trial < 20000; ++trial) {
    // Counts on both sides of the 64-bit path's limit (2^24 parallelograms).
    const unsigned count = trial % 2 ? 1 + static_cast<unsigned>(rng() % 8)
                                     : (1u << 24) - 4 + static_cast<unsigned>(rng() % 8);
    const std::int64_t per = trial % 5 ? std::int64_t(top) : 2048;
    // Sums of values in range: parallelograms in (−2^30, 2^31), edge ends in [0, 2^31).
    const std::int64_t s = (static_cast<std::int64_t>(rng() % (3 * per)) - per) * count;
    const std::int64_t e = static_cast<std::int64_t>(rng() % (2 * per)) * count;
    const unsigned k = static_cast<unsigned>(rng() % 16);
    ASSERT_EQ(blended_mean(s, e, count, k, top), blended_reference(s, e, count, k, top))
        << s << ' ' << e << ' ' << count << ' ' << k;
  }
}

/// A torus sampled irregularly (each grid vertex jittered along the surface), as a scan
/// is: parallelograms across uneven triangles miss, and their edges' centroid evens out.
test::Arrays irregular_torus(int nu, int nv, unsigned seed) {
  test::Arrays a = test::torus(nu, nv);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(-0.35, 0.35);
  const double pi = std::acos(-1.0);
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      const double u = 2 * pi * (i + jitter(rng)) / nu, v = 2 * pi * (j + jitter(rng)) / nv;
      a.points[j * nu + i] = Point((3 + std::cos(v)) * std::cos(u), (3 + std::cos(v)) * std::sin(u), std::sin(v));
    }
  return a;
}

/// The holey slab's corner table (its input shuffled by shuffle_seed) and random grid points
/// for it, n_isolated isolated vertices last; one coordinate in edge_one_in sits on the
/// grid's edge, so clamped predictions are exercised.
struct DegreeCase {
  CornerTable table;
  std::vector<QPoint> q;
  unsigned bits;
};

DegreeCase random_degree_case(unsigned shuffle_seed, unsigned rng_seed, unsigned bits,
                              std::size_t n_isolated, unsigned edge_one_in) {
  const FlatMesh flat = flatten(test::holey_slab(2, true).shuffled(shuffle_seed).build());
  RansEncoder conn_rans;
  BitWriter conn_raw;
  DegreeCase c{{}, {}, bits};
  TraversalOrder order;
  encode_connectivity(flat.table, flat.polygons, Traversal::kRightFirst, conn_rans, conn_raw,
                      c.table, order);
  std::mt19937 rng(rng_seed);
  const std::uint32_t top = (1u << bits) - 1;
  c.q.resize(c.table.n_vertices + n_isolated);
  for (QPoint& p : c.q)
    for (auto& x : p) x = rng() % edge_one_in == 0 ? (rng() % 2 ? top : 0) : rng() % (top + 1);
  return c;
}

/// Codes c's points with the fused degree pass and decodes them: the same traversal, the
/// same points.
void expect_degree_round_trip(const DegreeCase& c, Predictor predictor, Blend blend,
                              bool anchored = false) {
  CornerTable enc_table = c.table, dec_table = c.table;
  RansEncoder re;
  BitWriter bw;
  const auto seq = encode_positions_degree(enc_table, c.q, c.bits, re, bw, predictor, blend,
                                           nullptr, anchored);
  ASSERT_EQ(seq.size(), anchored ? c.q.size() : c.table.n_vertices);
  const std::vector<std::uint8_t> rans = re.finish(), raw = bw.finish();
  RansDecoder rd(rans, 0);
  BitReader br(raw, 0);
  std::vector<QPoint> decoded;
  const auto dec_seq =
      decode_positions_degree(dec_table, c.q.size(), c.bits, rd, br, decoded, predictor, blend,
                              anchored);
  ASSERT_EQ(dec_seq.size(), seq.size());
  EXPECT_TRUE(std::equal(seq.begin(), seq.begin() + c.table.n_vertices, dec_seq.begin()));
  rd.finish();
  for (std::size_t i = 0; i < c.q.size(); ++i)
    ASSERT_EQ(decoded[i], c.q[i < seq.size() ? seq[i] : i]) << "vertex " << i;
}

/// Round trips m at level 7, reordered and order-preserving: every vertex comes back (the
/// n_isolated isolated ones isolated) within the quantisation bound.
void expect_isolated_round_trip(const SurfaceMesh& m, std::size_t n_isolated) {
  for (bool preserve : {false, true}) {
    const CompressResult c = compress(m, {.level = 7, .preserve_order = preserve});
    const DecompressResult d = decompress(c.bytes);
    ASSERT_EQ(d.mesh.n_vertices(), m.n_vertices());
    std::size_t i = 0, isolated = 0;
    for (Vertex v : d.mesh.vertices()) {
      const Vertex orig(c.vertex_permutation[i++]);
      if (preserve) {
        ASSERT_EQ(orig, v);
      }
      ASSERT_EQ(d.mesh.is_isolated(v), m.is_isolated(orig)) << "vertex " << v.idx();
      isolated += d.mesh.is_isolated(v);
      ASSERT_LE((d.mesh.position(v) - m.position(orig)).cwiseAbs().maxCoeff(),
                c.stats.max_error * (1 + 1e-9))
          << "vertex " << v.idx();
    }
    EXPECT_EQ(isolated, n_isolated);
  }
}

/// Decodes c: every vertex of m comes back (through the permutation) within the bound.
void expect_decodes_within_bound(const SurfaceMesh& m, const CompressResult& c) {
  const DecompressResult d = decompress(c.bytes);
  ASSERT_EQ(d.mesh.n_vertices(), m.n_vertices());
  std::size_t i = 0;
  for (Vertex v : d.mesh.vertices()) {
    const Point& p = m.position(Vertex(c.vertex_permutation[i++]));
    ASSERT_LE((d.mesh.position(v) - p).cwiseAbs().maxCoeff(), c.stats.max_error * (1 + 1e-9));
  }
}

/// Flips one random bit of the stream per trial: decoding must throw DecodeError or give a
/// valid mesh, never crash or read out of bounds (ASan runs these too).
void expect_flips_throw_or_decode_valid(const std::vector<std::uint8_t>& bytes, unsigned seed,
                                        int trials) {
  std::mt19937 rng(seed);
  for (int trial = 0; trial < trials; ++trial) {
    std::vector<std::uint8_t> bad = bytes;
    bad[rng() % bad.size()] ^= static_cast<std::uint8_t>(1u << (rng() % 8));
    try {
      EXPECT_TRUE(validate(decompress(bad).mesh).ok());
    } catch (const DecodeError&) {
    }
  }
}

TEST(CompressBlend, RoundTripsExactlyWithEveryWeight) {
  const DegreeCase c = random_degree_case(4, 8, 12, 2, 4);  // two isolated vertices last
  for (const Blend blend : {Blend{0, 0}, Blend{1, 15}, Blend{15, 1}, Blend{6, 5}})
    expect_degree_round_trip(c, Predictor::kMultiParallelogramBlend, blend);
}

TEST(CompressBlend, ChosenOnIrregularSamplingAndSmaller) {
  const SurfaceMesh m = irregular_torus(60, 40, 2).build();
  const CompressResult c = compress(m, {.level = 5});
  EXPECT_EQ(c.stats.predictor, int(Predictor::kMultiParallelogramBlend));
  const FlatMesh flat = flatten(m);
  const Quantiser quant = quantiser_for_bits(flat.positions, 11);
  std::vector<QPoint> q;
  for (const Point& p : flat.positions) q.push_back(quant.quantise(p));
  auto geometry_bytes = [&](Blend blend, Blend* suggest) {
    CornerTable t = flat.table;
    RansEncoder re;
    BitWriter bw;
    encode_positions_degree(t, q, 11, re, bw, Predictor::kMultiParallelogramBlend, blend, suggest);
    return re.finish().size() + bw.finish().size();
  };
  Blend suggested;
  const std::size_t plain = geometry_bytes({}, &suggested);
  ASSERT_TRUE(suggested.any());
  EXPECT_LT(geometry_bytes(suggested, nullptr), plain);
  expect_decodes_within_bound(m, c);
}

TEST(CompressBlend, DamagedStreamsThrowOrDecodeValidMeshes) {
  const CompressResult c = compress(irregular_torus(16, 10, 3).build(), {.level = 5});
  ASSERT_EQ(c.stats.predictor, int(Predictor::kMultiParallelogramBlend));
  EXPECT_NE(c.bytes[40], 0);  // the blend byte (no attribute fields before it): weights in use
  for (std::size_t len = 0; len < c.bytes.size(); ++len)
    EXPECT_THROW(decompress(std::span(c.bytes.data(), len)), DecodeError) << len;
  expect_flips_throw_or_decode_valid(c.bytes, 41, 1500);
}

TEST(CompressBlend, FlatGridAtTheCheapestResidualsDecodes) {
  // All residuals zero: each costs the least its length model allows, well past the 64
  // vertices per geometry byte of predictors 0–3; the decoder's count check must allow it.
  // A flat 89 × 89 grid spans 2047 = 89 · 23 steps of the 11-bit grid: exact predictions.
  test::Arrays a = test::grid(89, 89);
  for (Point& p : a.points) p.z() = 0;
  const SurfaceMesh m = a.build();
  const CompressResult c = compress(m, {.level = 5});
  ASSERT_EQ(c.stats.predictor, int(Predictor::kMultiParallelogramBlend));
  EXPECT_GT(double(m.n_vertices()) / double(c.stats.geometry_bytes), 64.0);
  EXPECT_EQ(decompress(c.bytes).mesh.n_vertices(), m.n_vertices());
}

/// Predictor 5 through the fused passes: random positions (every mask gets chosen, clamping
/// at the grid's edges included) with and without blend weights, isolated vertices chained
/// or anchored, decode to the input.
TEST(CompressSelect, RoundTripsExactlyWithAndWithoutWeights) {
  const DegreeCase c = random_degree_case(5, 9, 10, 9, 5);  // nine isolated vertices last
  for (const bool anchored : {false, true})
    for (const Blend blend : {Blend{0, 0}, Blend{3, 9}})
      expect_degree_round_trip(c, Predictor::kMultiParallelogramSelect, blend, anchored);
}

TEST(NearestSites, AgreesWithBruteForce) {
  std::mt19937 rng(13);
  for (const unsigned n_sites : {1u, 7u, 500u}) {
    std::vector<QPoint> sites(n_sites), queries(300);
    auto below = [&](std::uint32_t n) { return static_cast<std::uint32_t>(rng() % n); };
    for (QPoint& p : sites) p = {below(1000), below(50), 400 + below(300)};
    for (QPoint& p : queries) p = {below(1300), below(1300), below(1300)};  // some outside
    sites.push_back(sites.front());  // a tie: the lower index wins
    const std::vector<std::uint32_t> got = nearest_sites(sites, queries);
    for (std::size_t i = 0; i < queries.size(); ++i) {
      auto d2 = [&](const QPoint& s) {
        std::uint64_t d = 0;
        for (int a = 0; a < 3; ++a) {
          const std::int64_t x = std::int64_t{s[a]} - std::int64_t{queries[i][a]};
          d += std::uint64_t(x * x);
        }
        return d;
      };
      std::uint32_t best = 0;
      for (std::uint32_t s = 1; s < sites.size(); ++s)
        if (d2(sites[s]) < d2(sites[best])) best = s;
      ASSERT_EQ(got[i], best) << n_sites << " sites, query " << i;
    }
  }
}

/// A torus with n isolated points close to its surface (a scan's left-out samples).
test::Arrays torus_with_near_points(unsigned n, unsigned seed) {
  test::Arrays a = test::torus(40, 24);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> angle(0, 2 * std::acos(-1.0)), off(-0.02, 0.02);
  for (unsigned i = 0; i < n; ++i) {
    const double u = angle(rng), v = angle(rng), r = 1 + off(rng);
    a.points.push_back(Point((3 + r * std::cos(v)) * std::cos(u),
                             (3 + r * std::cos(v)) * std::sin(u), r * std::sin(v)));
  }
  return a.shuffled(seed);
}

TEST(CompressSelect, AnchorsIsolatedPointsNearTheSurface) {
  const unsigned n = 400;
  const SurfaceMesh m = torus_with_near_points(n, 3).build();
  const CompressResult c = compress(m, {.level = 7});
  ASSERT_EQ(c.stats.predictor, int(Predictor::kMultiParallelogramSelect));
  EXPECT_EQ(c.bytes[41], 1);  // after the blend byte: isolated vertices anchored
  EXPECT_LT(c.bytes.size(), compress(m, {.level = 5}).bytes.size());
  expect_isolated_round_trip(m, n);
  // An anchor gap past the connected vertices is an error, not a read out of bounds: the
  // damaged-stream sweep below must only ever throw DecodeError or decode a valid mesh.
  expect_flips_throw_or_decode_valid(c.bytes, 17, 300);
}

/// A torus grid whose quads are split along a random diagonal each, as a range image's
/// zippered triangulation is, with its vertices moved by Gaussian noise of deviation `noise`.
test::Arrays flipped_torus(int nu, int nv, double noise, unsigned seed) {
  test::Arrays a = test::torus(nu, nv);
  std::mt19937 rng(seed);
  a.faces.clear();
  auto id = [&](int i, int j) { return static_cast<std::uint32_t>((j % nv) * nu + (i % nu)); };
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      const std::uint32_t q[4] = {id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)};
      const int d = static_cast<int>(rng() % 2);
      a.faces.push_back({q[d], q[d + 1], q[d + 2]});
      a.faces.push_back({q[d], q[d + 2], q[(d + 3) % 4]});
    }
  std::normal_distribution<double> g(0.0, noise);
  for (Point& p : a.points) p += Point(g(rng), g(rng), g(rng));
  return a;
}

TEST(CompressSelect, ChosenOnMixedDiagonalsAndDecodesWithinTheBound) {
  // Across a grid edge whose two triangles' diagonals disagree, a parallelogram predicts the
  // wrong grid point; choosing the parallelograms pays (about 13% smaller here, 30% without
  // the noise), as on the Stanford bunny's zippered range images.
  const SurfaceMesh m = flipped_torus(48, 32, 0.003, 5).build();
  const CompressResult c = compress(m, {.level = 7});
  EXPECT_EQ(c.stats.predictor, int(Predictor::kMultiParallelogramSelect));
  EXPECT_LT(double(c.bytes.size()), 0.9 * double(compress(m, {.level = 5}).bytes.size()));
  expect_decodes_within_bound(m, c);
  for (std::size_t len = 0; len < c.bytes.size(); len += 7)
    EXPECT_THROW(decompress(std::span(c.bytes.data(), len)), DecodeError) << len;
  expect_flips_throw_or_decode_valid(c.bytes, 12, 300);
}

/// A torus with n isolated points spread over a sphere around it, in random order.
test::Arrays torus_with_isolated(unsigned n, unsigned seed) {
  test::Arrays a = test::torus(20, 12);
  std::mt19937 rng(seed);
  std::normal_distribution<double> g;
  for (unsigned i = 0; i < n; ++i) {
    const Eigen::Vector3d d(g(rng), g(rng), g(rng));
    a.points.push_back(Point(3.5 * d.normalized()));
  }
  return a.shuffled(seed);
}

TEST(CompressIsolated, ChainedCheaplyAndDecodedWithinTheBound) {
  const unsigned n = 3000;
  const test::Arrays a = torus_with_isolated(n, 6);
  const SurfaceMesh m = a.build();
  expect_isolated_round_trip(m, n);
  // The isolated points alone, each coded as the delta from the one before: in their random
  // input order about 33 bits a point on this 11-bit grid, chained about 22.
  std::vector<Point> cloud(a.points.end() - n, a.points.end());
  const Quantiser quant = quantiser_for_bits(cloud, 11);
  std::vector<QPoint> in_order, chained;
  for (const Point& p : cloud) in_order.push_back(quant.quantise(p));
  for (std::uint32_t i : point_chain(in_order)) chained.push_back(in_order[i]);
  auto bits_per_point = [&](const std::vector<QPoint>& q) {
    CornerTable none;
    RansEncoder re;
    BitWriter bw;
    encode_positions_degree(none, q, 11, re, bw, Predictor::kMultiParallelogramBlend);
    return 8.0 * double(re.finish().size() + bw.finish().size()) / n;
  };
  const double random_order = bits_per_point(in_order), chain = bits_per_point(chained);
  EXPECT_GT(random_order, 30.0);
  EXPECT_LT(chain, 24.0);
}

}  // namespace
}  // namespace geom::codec::detail
