#include "evolve/evaluators/handoff_evaluator.hpp"

#include <stdexcept>
#include <string>

#include "evolve/problems/wire_format.hpp"

namespace sodaevo {

std::vector<Evaluation> HandoffEvaluator::evaluate(const std::vector<const soda::ModelDef*>& creatures,
                                                   const Problem& problem, const Estimator& estimator) {
  Request request;
  WireWriter head;
  problem.write(head);
  estimator.write(head);
  request.head = head.take();
  request.creatures.reserve(creatures.size());
  for (const soda::ModelDef* c : creatures) request.creatures.push_back(*c);

  std::unique_lock lock(mutex_);
  if (abandoned_) throw RunAbandoned{};
  expected_ = creatures.size();
  answers_.reset();
  request_ = std::move(request);
  waiting_ = true;
  changed_.notify_all();
  changed_.wait(lock, [&] { return answers_.has_value() || abandoned_; });
  waiting_ = false;
  if (abandoned_) throw RunAbandoned{};
  std::vector<Evaluation> out = std::move(*answers_);
  answers_.reset();
  return out;
}

std::optional<HandoffEvaluator::Request> HandoffEvaluator::wait_for_request() {
  std::unique_lock lock(mutex_);
  changed_.wait(lock, [&] { return request_.has_value() || ended_; });
  if (!request_) return std::nullopt;
  std::optional<Request> out = std::move(request_);
  request_.reset();
  return out;
}

void HandoffEvaluator::answer(std::vector<Evaluation> evaluations) {
  std::lock_guard lock(mutex_);
  if (!waiting_ || answers_) throw std::logic_error("HandoffEvaluator::answer: no request is waiting for answers");
  if (evaluations.size() != expected_) {
    throw std::invalid_argument(std::to_string(evaluations.size()) + " evaluations for a request of " +
                                std::to_string(expected_) + " creatures");
  }
  answers_ = std::move(evaluations);
  changed_.notify_all();
}

void HandoffEvaluator::loop_ended() {
  std::lock_guard lock(mutex_);
  ended_ = true;
  changed_.notify_all();
}

void HandoffEvaluator::abandon() {
  std::lock_guard lock(mutex_);
  abandoned_ = true;
  request_.reset();
  changed_.notify_all();
}

} // namespace sodaevo
