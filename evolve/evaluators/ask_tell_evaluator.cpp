#include "ask_tell_evaluator.hpp"

#include <cstdint>

#include "evolve/problems/wire_format.hpp"

namespace sodaevo {

namespace {

std::string as_key(const std::vector<char>& bytes) { return {bytes.begin(), bytes.end()}; }

} // namespace

std::vector<Evaluation> AskTellEvaluator::evaluate(const std::vector<const soda::ModelDef*>& creatures,
                                                   const Problem& problem, const Estimator& estimator) {
  WireWriter head;
  problem.write(head);
  estimator.write(head);
  WireWriter all = head;
  for (const soda::ModelDef* c : creatures) all.creature(*c);
  const std::string key = as_key(all.bytes());
  if (const auto it = answers_.find(key); it != answers_.end()) return it->second;
  pending_key_ = key;
  pending_head_ = head.take();
  pending_.clear();
  for (const soda::ModelDef* c : creatures) pending_.push_back(*c);
  told_.assign(creatures.size(), std::nullopt);
  throw NeedEvaluation{};
}

std::vector<char> AskTellEvaluator::chunk(std::size_t first, std::size_t last) const {
  WireWriter w;
  for (char c : pending_head_) w.u8(static_cast<std::uint8_t>(c));
  w.u32(static_cast<std::uint32_t>(last - first));
  for (std::size_t k = first; k < last; ++k) w.creature(pending_[k]);
  return w.take();
}

bool AskTellEvaluator::tell(std::size_t first, const char* bytes, std::size_t size) {
  std::vector<Evaluation> got = decode_evaluations(bytes, size);
  if (first + got.size() > told_.size()) throw WireError("results past the request's end");
  for (std::size_t k = 0; k < got.size(); ++k) told_[first + k] = std::move(got[k]);
  for (const auto& e : told_) {
    if (!e) return false;
  }
  std::vector<Evaluation> all;
  for (auto& e : told_) all.push_back(std::move(*e));
  answers_[pending_key_] = std::move(all);
  pending_.clear();
  told_.clear();
  return true;
}

} // namespace sodaevo
