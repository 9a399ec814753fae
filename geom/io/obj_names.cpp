#include <geom/io/obj_names.h>

namespace geom::io_detail {

std::uint32_t FaceNameTrack::index(const std::string& name) {
  const auto [it, added] = index_.try_emplace(name, static_cast<std::uint32_t>(names_.size()));
  if (added) names_.push_back(name);
  return it->second;
}

void FaceNameTrack::set(std::string_view name) {
  named_ = true;
  current_ = name.empty() ? FaceNames::kUnnamed : index(std::string(name));
}

void FaceNameTrack::face() {
  if (named_) of_face_.push_back(current_);
  else ++leading_;
}

void FaceNameTrack::append(const FaceNameTrack& later) {
  if (named_) of_face_.insert(of_face_.end(), later.leading_, current_);
  else leading_ += later.leading_;
  if (!later.named_) return;
  named_ = true;
  auto mine = [&](std::uint32_t i) { return i == FaceNames::kUnnamed ? i : index(later.names_[i]); };
  for (std::uint32_t i : later.of_face_) of_face_.push_back(mine(i));
  current_ = mine(later.current_);
}

FaceNames FaceNameTrack::finish() && {
  FaceNames out;
  if (names_.empty() || leading_ + of_face_.size() == 0) return out;  // nothing named
  out.names = std::move(names_);
  out.of_face.assign(leading_, FaceNames::kUnnamed);
  out.of_face.insert(out.of_face.end(), of_face_.begin(), of_face_.end());
  return out;
}

void write_face_name(const FaceNames& names, const char* keyword, std::size_t f, std::string& out) {
  if (names.of_face.empty()) return;
  const std::uint32_t now = names.of_face[f];
  if (now == (f == 0 ? FaceNames::kUnnamed : names.of_face[f - 1])) return;
  out += keyword;
  if (now != FaceNames::kUnnamed) (out += ' ') += names.names[now];
  out += '\n';
}

}  // namespace geom::io_detail
