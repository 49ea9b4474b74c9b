// The VTK filters' int constants (what Python and the ParaView XML use) are
// the values of the core's enum classes, joined by a cast.  Each adapter
// states the pairs with this macro, so a change on either side fails to
// compile; the XML's EnumerationDomain values are checked against the
// filters by the test Python.PluginXMLMatchesFilters.  Not wrapped.
#ifndef vtkBeltramiEnumCheck_h
#define vtkBeltramiEnumCheck_h

#define BELTRAMI_SAME_ENUM(vtkConstant, coreEnumerator)                                          \
  static_assert(static_cast<int>(vtkConstant) == static_cast<int>(coreEnumerator),               \
    #vtkConstant " must equal " #coreEnumerator)

#endif
// VTK-HeaderTest-Exclude: vtkBeltramiEnumCheck.h
