#include <geom/core/errors.h>
#include <geom/io/grid.h>
#include <geom/isosurface/grid.h>

#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>

using namespace geom;

namespace {

/// A .npy file image: version, header dict text and raw payload bytes.
std::vector<std::byte> npy(const std::string& dict, const std::vector<unsigned char>& payload,
                           int version = 1) {
  std::string header = dict;
  std::size_t prefix = version == 1 ? 10 : 12;
  header.append((64 - (prefix + header.size() + 1) % 64) % 64, ' ');
  header.push_back('\n');
  std::string out = std::string("\x93NUMPY", 6) + char(version) + char(0);
  std::size_t n = header.size();
  out += char(n & 0xff);
  out += char((n >> 8) & 0xff);
  if (version != 1) {
    out += char((n >> 16) & 0xff);
    out += char((n >> 24) & 0xff);
  }
  out += header;
  out.append(reinterpret_cast<const char*>(payload.data()), payload.size());
  std::vector<std::byte> bytes(out.size());
  std::memcpy(bytes.data(), out.data(), out.size());
  return bytes;
}

template <class T>
std::vector<unsigned char> raw_bytes(const std::vector<T>& v, bool big = false) {
  std::vector<unsigned char> out(v.size() * sizeof(T));
  std::memcpy(out.data(), v.data(), out.size());
  if (big)
    for (std::size_t i = 0; i < v.size(); ++i) std::reverse(out.begin() + i * sizeof(T), out.begin() + (i + 1) * sizeof(T));
  return out;
}

}  // namespace

TEST(GridIo, ReadsCOrderFloat32WithoutReordering) {
  std::vector<float> v(2 * 3 * 4);
  for (std::size_t i = 0; i < v.size(); ++i) v[i] = float(i) * 0.5f;
  GridData g = read_npy(npy("{'descr': '<f4', 'fortran_order': False, 'shape': (2, 3, 4), }", raw_bytes(v)));
  EXPECT_EQ(g.nx, 4u);
  EXPECT_EQ(g.ny, 3u);
  EXPECT_EQ(g.nz, 2u);
  EXPECT_FALSE(g.is_double);
  EXPECT_EQ(g.floats, v);
  ScalarGrid grid({g.nx, g.ny, g.nz}, std::move(g.floats));
  EXPECT_EQ(grid.at(3, 2, 1), 23 * 0.5);  // a[1, 2, 3] = (x 3, y 2, z 1)
}

TEST(GridIo, FortranOrderIsTransposedToTheSameLogicalArray) {
  // Logical a[i, j, k] = 100 i + 10 j + k, shape (2, 3, 4), stored with i fastest.
  std::vector<double> f;
  for (int k = 0; k < 4; ++k)
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 2; ++i) f.push_back(100 * i + 10 * j + k);
  GridData g = read_npy(npy("{'descr': '<f8', 'fortran_order': True, 'shape': (2, 3, 4), }", raw_bytes(f), 2));
  ASSERT_TRUE(g.is_double);
  ScalarGrid grid({g.nx, g.ny, g.nz}, std::move(g.doubles));
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 4; ++k) EXPECT_EQ(grid.at(k, j, i), 100 * i + 10 * j + k);
}

TEST(GridIo, OtherDtypesAreConverted) {
  std::vector<std::int16_t> i2 = {-3, 0, 7, 1000};
  GridData a = read_npy(npy("{'descr': '>i2', 'fortran_order': False, 'shape': (4,), }", raw_bytes(i2, true)));
  EXPECT_EQ(a.floats, (std::vector<float>{-3, 0, 7, 1000}));
  EXPECT_EQ(a.nx, 4u);
  EXPECT_EQ(a.ny, 1u);
  std::vector<std::uint8_t> u1 = {0, 255, 3, 4, 5, 6};
  GridData b = read_npy(npy("{'descr': '|u1', 'fortran_order': False, 'shape': (2, 3), }", raw_bytes(u1)));
  EXPECT_EQ(b.floats, (std::vector<float>{0, 255, 3, 4, 5, 6}));
  EXPECT_EQ(b.ny, 2u);
  std::vector<std::int64_t> i8 = {-(std::int64_t(1) << 40), 5};
  GridData c = read_npy(npy("{'descr': '<i8', 'fortran_order': False, 'shape': (2,), }", raw_bytes(i8)));
  ASSERT_TRUE(c.is_double);
  EXPECT_EQ(c.doubles[0], -std::ldexp(1.0, 40));
  std::vector<std::uint16_t> f2 = {0x3c00, 0xc000, 0x7c00};  // 1, -2, inf
  GridData d = read_npy(npy("{'descr': '<f2', 'fortran_order': False, 'shape': (3,), }", raw_bytes(f2)));
  EXPECT_EQ(d.floats[0], 1.0f);
  EXPECT_EQ(d.floats[1], -2.0f);
  EXPECT_TRUE(std::isinf(d.floats[2]));
  std::vector<float> bigf = {1.5f, -2.25f};
  GridData e = read_npy(npy("{'descr': '>f4', 'fortran_order': False, 'shape': (1, 1, 2), }", raw_bytes(bigf, true), 3));
  EXPECT_EQ(e.floats, bigf);
  std::vector<std::uint8_t> b1 = {1, 0};
  EXPECT_EQ(read_npy(npy("{'descr': '|b1', 'fortran_order': False, 'shape': (2,), }", raw_bytes(b1))).floats,
            (std::vector<float>{1, 0}));
}

TEST(GridIo, MalformedNpyThrowsParseError) {
  std::vector<float> v(8, 1.f);
  auto ok = npy("{'descr': '<f4', 'fortran_order': False, 'shape': (2, 2, 2), }", raw_bytes(v));
  EXPECT_NO_THROW(read_npy(ok));
  auto bad_magic = ok;
  bad_magic[1] = std::byte{'X'};
  EXPECT_THROW(read_npy(bad_magic), ParseError);
  auto truncated = ok;
  truncated.resize(truncated.size() - 1);
  EXPECT_THROW(read_npy(truncated), ParseError);
  EXPECT_THROW(read_npy(std::span<const std::byte>(ok.data(), 5)), ParseError);
  auto bad_version = ok;
  bad_version[6] = std::byte{9};
  EXPECT_THROW(read_npy(bad_version), ParseError);
  auto long_header = ok;
  long_header[9] = std::byte{0x7f};
  EXPECT_THROW(read_npy(long_header), ParseError);
  EXPECT_THROW(read_npy(npy("{'descr': '<c8', 'fortran_order': False, 'shape': (1,), }", raw_bytes(v))), ParseError);
  EXPECT_THROW(read_npy(npy("{'descr': '|O', 'fortran_order': False, 'shape': (1,), }", raw_bytes(v))), ParseError);
  EXPECT_THROW(read_npy(npy("{'descr': '<f4', 'fortran_order': False, 'shape': (1, 2, 2, 2), }", raw_bytes(v))), ParseError);
  EXPECT_THROW(read_npy(npy("{'descr': '<f4', 'shape': (8,), }", raw_bytes(v))), ParseError);
  EXPECT_THROW(read_npy(npy("{'descr': '<f4', 'fortran_order': False, 'shape': (99999999999, 99999999999), }", raw_bytes(v))),
               ParseError);
  EXPECT_THROW(read_npy(npy("{'descr': '<f4', 'fortran_order': False, 'shape': (2, x), }", raw_bytes(v))), ParseError);
  try {
    read_npy(truncated, "vol.npy");
  } catch (const ParseError& e) {
    EXPECT_EQ(e.file(), "vol.npy");
    EXPECT_EQ(e.unit(), ParseError::Unit::kByte);
  }
}

// Found by fuzz_npy: an empty array (a zero in the shape) reached memcpy with a null
// destination (UBSan). It reads as an empty grid, which the isosurface then refuses by name.
TEST(GridIo, EmptyArrayReadsAsAnEmptyGridThatMarchingCubesRefuses) {
  for (const char* descr : {"<f4", "<f8", ">i2"}) {
    const std::string dict = std::string("{'descr': '") + descr + "', 'fortran_order': False, 'shape': (2, 3, 0), }";
    GridData g = read_npy(npy(dict, {}));
    EXPECT_EQ(g.nx, 0u);
    EXPECT_EQ(g.ny, 3u);
    EXPECT_EQ(g.nz, 2u);
    EXPECT_TRUE(g.floats.empty() && g.doubles.empty());
  }
  EXPECT_THROW(ScalarGrid({0, 3, 2}, std::vector<float>{}), InvalidArgument);
}

TEST(GridIo, WriteNpyRoundTripsAndRawReads) {
  auto dir = std::filesystem::temp_directory_path() / "geom_test_grid_io";
  std::filesystem::create_directories(dir);
  std::vector<float> v(3 * 4 * 5);
  for (std::size_t i = 0; i < v.size(); ++i) v[i] = float(i) - 7.f;
  write_npy(dir / "a.npy", 3, 4, 5, std::span<const float>(v));
  GridData g = read_npy(dir / "a.npy");
  EXPECT_EQ(g.nx, 3u);
  EXPECT_EQ(g.nz, 5u);
  EXPECT_EQ(g.floats, v);
  std::vector<double> dv(v.begin(), v.end());
  write_npy(dir / "b.npy", 3, 4, 5, std::span<const double>(dv));
  EXPECT_EQ(read_npy(dir / "b.npy").doubles, dv);
  EXPECT_THROW(write_npy(dir / "c.npy", 3, 4, 4, std::span<const float>(v)), InvalidArgument);

  {
    std::ofstream f(dir / "r.raw", std::ios::binary);
    f.write("HDR!", 4);
    f.write(reinterpret_cast<const char*>(v.data()), std::streamsize(v.size() * 4));
  }
  GridData r = read_raw(dir / "r.raw", {.nx = 3, .ny = 4, .nz = 5, .dtype = "f4", .offset = 4});
  EXPECT_EQ(r.floats, v);
  // Same bytes read as z fastest: sample (x, y, z) is file element z + 5 (y + 4 x).
  GridData t = read_raw(dir / "r.raw", {.nx = 3, .ny = 4, .nz = 5, .dtype = "<f4", .z_fastest = true, .offset = 4});
  EXPECT_EQ(t.floats[1 + 3 * (2 + 4 * 3)], v[3 + 5 * (2 + 4 * 1)]);
  EXPECT_THROW(read_raw(dir / "r.raw", {.nx = 3, .ny = 4, .nz = 6, .offset = 4}), ParseError);
  EXPECT_THROW(read_raw(dir / "r.raw", {.nx = 3, .ny = 4, .nz = 5, .dtype = "q9"}), InvalidArgument);
  EXPECT_THROW(read_raw(dir / "r.raw", {.nx = 0, .ny = 4, .nz = 5}), InvalidArgument);
  EXPECT_THROW(read_npy(dir / "missing.npy"), Error);
  std::filesystem::remove_all(dir);
}
