#pragma once
// Internal: the per-thread pool of the Hessian blocks of large ad::EomJet
// numbers (eom_jet.hpp).

#include <vector>

namespace lagrangian::ad::detail {

/// Per-thread free list of blocks of type B (the Hessian parts of large
/// ad::EomJet numbers). A block is allocated only when the list is empty,
/// so once a thread has evaluated a model, later evaluations allocate
/// nothing; the blocks are freed when the thread ends.
template <class B>
class SecondPool {
 public:
  static B* take() {
    std::vector<B*>& f = list().free;
    if (f.empty()) return new B;
    B* b = f.back();
    f.pop_back();
    return b;
  }
  static void give(B* b) { list().free.push_back(b); }

 private:
  struct List {
    std::vector<B*> free;
    List() { free.reserve(64); }
    ~List() {
      for (B* b : free) delete b;
    }
    List(const List&) = delete;
    List& operator=(const List&) = delete;
  };
  static List& list() {
    thread_local List l;
    return l;
  }
};

}  // namespace lagrangian::ad::detail
