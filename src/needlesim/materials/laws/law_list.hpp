#pragma once
// The registry of constitutive laws: one line per law, X(LawKind enumerator,
// function returning its LawUnit). Each law is one file of this folder
// (law_unit.hpp says what it declares); its line here gives it a LawKind and
// puts it into lawUnits(), which the scenario schema and reader, `needlesim
// fit` and the engines ask. The order is the order they list the laws in.
#define NEEDLESIM_LAWS(X)        \
  X(Linear, linearLaw)           \
  X(NeoHookean, neoHookeanLaw)   \
  X(MooneyRivlin, mooneyRivlinLaw) \
  X(Yeoh, yeohLaw)               \
  X(Ogden, ogdenLaw)             \
  X(Fung, fungLaw)
