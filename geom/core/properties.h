#pragma once
/// \file
/// Named, typed per-element property arrays (structure of arrays). A `Property<H, T>` is a
/// cheap handle to one array; it stays valid while the mesh lives and the property is not
/// removed, across any number of element insertions.

#include <geom/core/errors.h>
#include <geom/core/handles.h>
#include <geom/core/huge_pages.h>

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <type_traits>
#include <typeinfo>
#include <vector>

namespace geom {

namespace detail {

/// The value new elements get when a property names none: zero for Eigen vectors (whose
/// default constructor leaves them uninitialised), value-initialised otherwise.
template <class T>
T zero_value() {
  if constexpr (requires { T::Zero(); }) return T::Zero();
  else return T{};
}

class BasePropertyArray {
 public:
  explicit BasePropertyArray(std::string name) : name_(std::move(name)) {}
  virtual ~BasePropertyArray() = default;
  virtual void reserve(std::size_t n) = 0;
  virtual void resize(std::size_t n) = 0;
  virtual void push_back() = 0;
  virtual void shrink_to_fit() = 0;
  /// Keep element `old_of_new[i]` at position i; the array shrinks to old_of_new.size().
  virtual void gather(std::span<const std::uint32_t> old_of_new) = 0;
  virtual std::unique_ptr<BasePropertyArray> clone() const = 0;
  virtual const std::type_info& type() const = 0;
  const std::string& name() const { return name_; }

 private:
  std::string name_;
};

template <class T>
class PropertyArray final : public BasePropertyArray {
  // std::vector<bool> hands out proxies, not references; use std::uint8_t for flags.
  static_assert(!std::is_same_v<T, bool>, "use std::uint8_t for boolean properties");

 public:
  PropertyArray(std::string name, T default_value)
      : BasePropertyArray(std::move(name)), default_(std::move(default_value)) {}
  void reserve(std::size_t n) override { data_.reserve(n); }
  void resize(std::size_t n) override { resize_prefaulted(data_, n, default_); }
  void push_back() override { data_.push_back(default_); }
  void shrink_to_fit() override { data_.shrink_to_fit(); }
  void gather(std::span<const std::uint32_t> old_of_new) override {
    std::vector<T> out;
    out.reserve(old_of_new.size());
    for (std::uint32_t i : old_of_new) out.push_back(data_[i]);  // an index may repeat
    data_.swap(out);
  }
  std::unique_ptr<BasePropertyArray> clone() const override {
    return std::make_unique<PropertyArray>(*this);
  }
  const std::type_info& type() const override { return typeid(T); }

  std::vector<T>& vector() { return data_; }
  const std::vector<T>& vector() const { return data_; }
  const T& default_value() const { return default_; }

 private:
  std::vector<T> data_;
  T default_;
};

}  // namespace detail

/// Handle to one property array indexed by element handles of kind H. Use
/// `Property<H, const T>` for read-only access (what a const mesh hands out).
template <class H, class T>
class Property {
  using Value = std::remove_const_t<T>;
  using Array = std::conditional_t<std::is_const_v<T>, const detail::PropertyArray<Value>,
                                   detail::PropertyArray<Value>>;

 public:
  Property() = default;
  explicit Property(Array* array) : array_(array) {}
  /// A read-write property converts to a read-only one.
  operator Property<H, const Value>() const { return Property<H, const Value>(array_); }

  explicit operator bool() const { return array_ != nullptr; }
  T& operator[](H h) const { return array_->vector()[h.idx()]; }
  auto& vector() const { return array_->vector(); }
  std::span<T> span() const { return {array_->vector().data(), array_->vector().size()}; }
  const std::string& name() const { return array_->name(); }

 private:
  Array* array_ = nullptr;
};

/// All property arrays of one element kind, kept at the same length.
class PropertyContainer {
 public:
  PropertyContainer() = default;
  PropertyContainer(const PropertyContainer& other) { *this = other; }
  PropertyContainer& operator=(const PropertyContainer& other) {
    if (this == &other) return *this;
    arrays_.clear();
    for (const auto& a : other.arrays_) arrays_.push_back(a->clone());
    size_ = other.size_;
    return *this;
  }
  PropertyContainer(PropertyContainer&&) noexcept = default;
  PropertyContainer& operator=(PropertyContainer&&) noexcept = default;

  /// Throws: InvalidArgument when a property of that name exists.
  template <class T>
  detail::PropertyArray<T>* add(const std::string& name, T default_value) {
    if (find(name)) throw InvalidArgument("property '" + name + "' already exists");
    auto array = std::make_unique<detail::PropertyArray<T>>(name, std::move(default_value));
    array->resize(size_);
    auto* raw = array.get();
    arrays_.push_back(std::move(array));
    return raw;
  }
  /// nullptr when there is no property of that name and type.
  template <class T>
  detail::PropertyArray<T>* get(const std::string& name) const {
    auto* base = find(name);
    if (!base || base->type() != typeid(T)) return nullptr;
    return static_cast<detail::PropertyArray<T>*>(base);
  }
  bool exists(const std::string& name) const { return find(name) != nullptr; }
  /// The element type of a named property, or nullptr.
  const std::type_info* type_of(const std::string& name) const {
    auto* base = find(name);
    return base ? &base->type() : nullptr;
  }
  void remove(const std::string& name) {
    std::erase_if(arrays_, [&](const auto& a) { return a->name() == name; });
  }
  std::vector<std::string> names() const {
    std::vector<std::string> out;
    for (const auto& a : arrays_) out.push_back(a->name());
    return out;
  }

  std::size_t size() const { return size_; }
  void reserve(std::size_t n) {
    for (auto& a : arrays_) a->reserve(n);
  }
  void resize(std::size_t n) {
    for (auto& a : arrays_) a->resize(n);
    size_ = n;
  }
  void push_back() {
    for (auto& a : arrays_) a->push_back();
    ++size_;
  }
  void shrink_to_fit() {
    for (auto& a : arrays_) a->shrink_to_fit();
  }
  void gather(std::span<const std::uint32_t> old_of_new) {
    for (auto& a : arrays_) a->gather(old_of_new);
    size_ = old_of_new.size();
  }

 private:
  detail::BasePropertyArray* find(const std::string& name) const {
    for (const auto& a : arrays_)
      if (a->name() == name) return a.get();
    return nullptr;
  }

  std::vector<std::unique_ptr<detail::BasePropertyArray>> arrays_;
  std::size_t size_ = 0;
};

}  // namespace geom
