#include <petsc.h>
/* Function forms of PETSc macros, defined in shim.c. */
PetscErrorCode ubr_log_event_begin(PetscLogEvent e);
PetscErrorCode ubr_log_event_end(PetscLogEvent e);
MPI_Comm ubr_comm_self(void);
PetscErrorCode ubr_free(void *p);
