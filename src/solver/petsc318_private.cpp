// The one file that reaches into PETSc's private structures, for PETSc 3.18
// only: the operations table of a PC (so that a lever is a PC type of its
// own, as PETSc's built-in ones are), GAMG's coarsening, whose aggregates
// -solver_damage_aggregates splits, and an object's state counter, which the
// single-precision cycle reads to see K change.  The first two change
// between PETSc versions; porting means reading this file against the new
// headers.
#include "petsc318_private.hpp"

#include "lem/base/error.hpp"

#include <petscversion.h>

#if !(PETSC_VERSION_MAJOR == 3 && PETSC_VERSION_MINOR == 18)
#error \
    "src/solver/petsc318_private.cpp is written against PETSc 3.18's private headers (PC operations, GAMG's coarsening); this PETSc is another version: port the file first"
#endif

#include <petsc/private/pcgamgimpl.h>
#include <petsc/private/pcimpl.h>
#include <petscmatcoarsen.h>

#include <algorithm>
#include <cstring>
#include <utility>
#include <vector>

namespace lem {

void define_pc_type(PC pc, void* data, const PcOperations& ops) {
  pc->data = data;
  pc->ops->setup = ops.setup;
  pc->ops->apply = ops.apply;
  pc->ops->destroy = ops.destroy;
  pc->ops->view = ops.view;
}

void* pc_type_data(PC pc) { return pc->data; }

void clear_pc_type_data(PC pc) { pc->data = nullptr; }

PetscObjectState object_state(PetscObject object) {
  PetscObjectState state = 0;
  LEM_PETSC(PetscObjectStateGet(object, &state));
  return state;
}

namespace {

// A piece smaller than this carries the six rigid modes badly or not at all
// (one node spans three of them, two nodes five: zero columns of the
// prolongator, zero rows on the coarse level): it joins a neighbouring one.
constexpr std::size_t kMinPiece = 4;

constexpr const char* kMarksName = "lem_damage_marks";

struct DamageMarks {
  std::vector<char> near_damage;  // per owned node: its aggregate is split
};

using CoarsenFunction = PetscErrorCode (*)(PC, Mat*, PetscCoarsenData**);
CoarsenFunction gamg_coarsen = nullptr;  // GAMG's own (the same for every PC)

PetscErrorCode destroy_marks(void* p) {
  delete static_cast<DamageMarks*>(p);
  return 0;
}

PC_GAMG* gamg_of(PC pc) { return static_cast<PC_GAMG*>(static_cast<PC_MG*>(pc->data)->innerctx); }

// The members of one aggregate (global node numbers) and their pieces.
struct Aggregate {
  std::vector<PetscInt> gids;
  std::vector<int> piece;
  std::vector<std::pair<PetscInt, int>> sorted;  // (gid, member) for lookups

  int member(PetscInt gid) const {
    auto it = std::lower_bound(sorted.begin(), sorted.end(), std::make_pair(gid, -1));
    return it != sorted.end() && it->first == gid ? it->second : -1;
  }
};

// Greedy pieces one bond across inside the aggregate: each unclaimed owned
// member claims its unclaimed neighbours of the graph; members of other
// ranks, whose rows are not here, go with the first piece.  Returns the
// number of pieces.
PetscErrorCode cut_pieces(Mat graph, PetscInt rstart, PetscInt rend, Aggregate& a, int* pieces) {
  PetscFunctionBeginUser;
  int count = 0;
  const std::size_t n = a.gids.size();
  a.piece.assign(n, -1);
  for (std::size_t i = 0; i < n; ++i) {
    const PetscInt gid = a.gids[i];
    if (gid < rstart || gid >= rend || a.piece[i] >= 0) continue;
    const int p = count++;
    a.piece[i] = p;
    PetscInt ncols;
    const PetscInt* cols;
    PetscCall(MatGetRow(graph, gid, &ncols, &cols, nullptr));
    for (PetscInt c = 0; c < ncols; ++c) {
      const int j = a.member(cols[c]);
      if (j >= 0 && a.piece[j] < 0) a.piece[j] = p;
    }
    PetscCall(MatRestoreRow(graph, gid, &ncols, &cols, nullptr));
  }
  for (int& p : a.piece)
    if (p < 0) p = 0;
  *pieces = count;
  PetscFunctionReturn(0);
}

// Merge pieces smaller than kMinPiece into a piece they touch (or the
// largest one), until every piece is large enough or one is left.
PetscErrorCode merge_small_pieces(Mat graph, PetscInt rstart, PetscInt rend, Aggregate& a,
                                  int pieces) {
  PetscFunctionBeginUser;
  for (;;) {
    std::vector<std::size_t> size(pieces, 0);
    for (int p : a.piece) ++size[p];
    int live = 0, smallest = -1, largest = -1;
    for (int p = 0; p < pieces; ++p) {
      if (!size[p]) continue;
      ++live;
      if (smallest < 0 || size[p] < size[smallest]) smallest = p;
      if (largest < 0 || size[p] > size[largest]) largest = p;
    }
    if (live <= 1 || size[smallest] >= kMinPiece) break;
    int into = -1;
    for (std::size_t i = 0; i < a.gids.size() && into < 0; ++i) {
      if (a.piece[i] != smallest || a.gids[i] < rstart || a.gids[i] >= rend) continue;
      PetscInt ncols;
      const PetscInt* cols;
      PetscCall(MatGetRow(graph, a.gids[i], &ncols, &cols, nullptr));
      for (PetscInt c = 0; c < ncols && into < 0; ++c) {
        const int j = a.member(cols[c]);
        if (j >= 0 && a.piece[j] != smallest) into = a.piece[j];
      }
      PetscCall(MatRestoreRow(graph, a.gids[i], &ncols, &cols, nullptr));
    }
    if (into < 0) into = largest == smallest ? -1 : largest;
    if (into < 0) break;
    for (int& p : a.piece)
      if (p == smallest) p = into;
  }
  PetscFunctionReturn(0);
}

PetscErrorCode split_near_damage(Mat graph, const DamageMarks& marks, PetscCoarsenData* lists,
                                 PetscInt* split, PetscInt* added) {
  PetscFunctionBeginUser;
  PetscInt rstart, rend;
  PetscCall(MatGetOwnershipRange(graph, &rstart, &rend));
  const PetscInt nloc = rend - rstart;
  PetscCheck(static_cast<std::size_t>(nloc) == marks.near_damage.size(), PETSC_COMM_SELF,
             PETSC_ERR_PLIB, "graph rows %" PetscInt_FMT " != owned nodes %zu", nloc,
             marks.near_damage.size());
  std::vector<PetscInt> aggregates, free_slots;
  for (PetscInt s = 0; s < nloc; ++s) {
    PetscBool empty;
    PetscCall(PetscCDEmptyAt(lists, s, &empty));
    (empty ? free_slots : aggregates).push_back(s);
  }
  std::size_t next_free = 0;
  Aggregate a;
  for (const PetscInt s : aggregates) {
    a.gids.clear();
    bool damaged = false;
    PetscCDIntNd* pos;
    PetscCall(PetscCDGetHeadPos(lists, s, &pos));
    while (pos) {
      PetscInt gid;
      PetscCall(PetscCDIntNdGetID(pos, &gid));
      PetscCall(PetscCDGetNextPos(lists, s, &pos));
      a.gids.push_back(gid);
      if (gid >= rstart && gid < rend && marks.near_damage[gid - rstart]) damaged = true;
    }
    if (!damaged || a.gids.size() < 2 * kMinPiece) continue;
    a.sorted.clear();
    for (std::size_t i = 0; i < a.gids.size(); ++i)
      a.sorted.emplace_back(a.gids[i], static_cast<int>(i));
    std::sort(a.sorted.begin(), a.sorted.end());
    int pieces = 0;
    PetscCall(cut_pieces(graph, rstart, rend, a, &pieces));
    PetscCall(merge_small_pieces(graph, rstart, rend, a, pieces));
    // Renumber the pieces left; the first member's stays in slot s.
    std::vector<int> slot_of(pieces, -1);
    slot_of[a.piece[0]] = static_cast<int>(s);
    int extra = 0;
    for (int p : a.piece)
      if (slot_of[p] < 0) {
        PetscCheck(next_free < free_slots.size(), PETSC_COMM_SELF, PETSC_ERR_PLIB,
                   "no free aggregate slot");
        slot_of[p] = static_cast<int>(free_slots[next_free++]);
        ++extra;
      }
    if (!extra) continue;
    PetscCall(PetscCDRemoveAll(lists, s));
    for (std::size_t i = 0; i < a.gids.size(); ++i)
      PetscCall(PetscCDAppendID(lists, slot_of[a.piece[i]], a.gids[i]));
    ++*split;
    *added += extra;
  }
  PetscFunctionReturn(0);
}

// GAMG's coarsening, then the split on the finest level.
PetscErrorCode coarsen_near_damage(PC pc, Mat* graph, PetscCoarsenData** lists) {
  PetscFunctionBeginUser;
  DamageMarks* marks = nullptr;
  PetscContainer container = nullptr;
  PetscCall(PetscObjectQuery(reinterpret_cast<PetscObject>(pc), kMarksName,
                             reinterpret_cast<PetscObject*>(&container)));
  if (container) PetscCall(PetscContainerGetPointer(container, reinterpret_cast<void**>(&marks)));
  if (!marks || gamg_of(pc)->current_level != 0) {
    PetscCall(gamg_coarsen(pc, graph, lists));
    PetscFunctionReturn(0);
  }
  // GAMG's coarsening may replace the graph (MIS-2 returns a matrix of its
  // own): keep the graph of K for the split.
  Mat plain = *graph;
  PetscCall(PetscObjectReference(reinterpret_cast<PetscObject>(plain)));
  PetscCall(gamg_coarsen(pc, graph, lists));
  PetscInt split = 0, added = 0;
  PetscCall(split_near_damage(plain, *marks, *lists, &split, &added));
  PetscCall(MatDestroy(&plain));
  PetscCall(PetscInfo(pc,
                      "damage aggregation: %" PetscInt_FMT " aggregates split, %" PetscInt_FMT
                      " added on this rank\n",
                      split, added));
  PetscFunctionReturn(0);
}

}  // namespace

bool is_gamg_aggregation(PC pc) {
  PetscBool gamg = PETSC_FALSE;
  LEM_PETSC(PetscObjectTypeCompare(reinterpret_cast<PetscObject>(pc), PCGAMG, &gamg));
  PC_GAMG* g = gamg ? gamg_of(pc) : nullptr;
  return g && g->ops && std::strcmp(g->type, PCGAMGAGG) == 0;
}

void split_aggregates_near(PC pc, std::vector<char> near_damage) {
  PC_GAMG* g = gamg_of(pc);
  if (g->ops->coarsen != coarsen_near_damage) {
    gamg_coarsen = g->ops->coarsen;
    g->ops->coarsen = coarsen_near_damage;
  }
  auto* marks = new DamageMarks;
  marks->near_damage = std::move(near_damage);
  PetscContainer container;
  LEM_PETSC(PetscContainerCreate(PETSC_COMM_SELF, &container));
  LEM_PETSC(PetscContainerSetPointer(container, marks));
  LEM_PETSC(PetscContainerSetUserDestroy(container, destroy_marks));
  LEM_PETSC(PetscObjectCompose(reinterpret_cast<PetscObject>(pc), kMarksName,
                               reinterpret_cast<PetscObject>(container)));
  LEM_PETSC(PetscContainerDestroy(&container));
}

}  // namespace lem
