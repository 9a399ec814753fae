#pragma once
/// \file
/// Ranges over the elements of a SurfaceMesh and around vertices and faces. They are light
/// views: valid while the mesh's connectivity is not edited.

#include <geom/core/handles.h>

#include <cstddef>
#include <iterator>

namespace geom {

class SurfaceMesh;

/// All live (not deleted) elements of one kind, in index order.
template <class H>
class ElementRange {
 public:
  class Iterator {
   public:
    using value_type = H;
    using difference_type = std::ptrdiff_t;
    Iterator() = default;
    Iterator(const SurfaceMesh* mesh, std::uint32_t i, std::uint32_t end)
        : mesh_(mesh), i_(i), end_(end) {
      skip();
    }
    H operator*() const { return H(i_); }
    Iterator& operator++() {
      ++i_;
      skip();
      return *this;
    }
    Iterator operator++(int) {
      Iterator t = *this;
      ++*this;
      return t;
    }
    bool operator==(const Iterator& o) const { return i_ == o.i_; }

   private:
    void skip();
    const SurfaceMesh* mesh_ = nullptr;
    std::uint32_t i_ = 0, end_ = 0;
  };

  ElementRange(const SurfaceMesh* mesh, std::uint32_t end) : mesh_(mesh), end_(end) {}
  Iterator begin() const { return {mesh_, 0, end_}; }
  Iterator end() const { return {mesh_, end_, end_}; }

 private:
  const SurfaceMesh* mesh_;
  std::uint32_t end_;
};

/// A circulation around a vertex or a face: starts at a halfedge, steps with Step, yields
/// Map(halfedge). Empty when the start is invalid (an isolated vertex).
template <class Value, class Step, class Map>
class CirculatorRange {
 public:
  class Iterator {
   public:
    using value_type = Value;
    using difference_type = std::ptrdiff_t;
    Iterator() = default;
    Iterator(const SurfaceMesh* mesh, Halfedge h, bool done) : mesh_(mesh), start_(h), h_(h), done_(done) {}
    Value operator*() const { return Map{}(*mesh_, h_); }
    Iterator& operator++() {
      h_ = Step{}(*mesh_, h_);
      done_ = (h_ == start_);
      return *this;
    }
    Iterator operator++(int) {
      Iterator t = *this;
      ++*this;
      return t;
    }
    bool operator==(const Iterator& o) const { return done_ == o.done_ && h_ == o.h_; }
    /// The halfedge the iterator stands on.
    Halfedge halfedge() const { return h_; }

   private:
    const SurfaceMesh* mesh_ = nullptr;
    Halfedge start_, h_;
    bool done_ = true;
  };

  CirculatorRange(const SurfaceMesh* mesh, Halfedge start) : mesh_(mesh), start_(start) {}
  Iterator begin() const { return {mesh_, start_, !start_.is_valid()}; }
  Iterator end() const { return {mesh_, start_, true}; }

 private:
  const SurfaceMesh* mesh_;
  Halfedge start_;
};

}  // namespace geom
