#include <petsc.h>
/* PETSc's log-event calls are macros; Rust calls these functions. */
PetscErrorCode ubr_log_event_begin(PetscLogEvent e) { return PetscLogEventBegin(e, 0, 0, 0, 0); }
PetscErrorCode ubr_log_event_end(PetscLogEvent e) { return PetscLogEventEnd(e, 0, 0, 0, 0); }
MPI_Comm ubr_comm_self(void) { return PETSC_COMM_SELF; }
PetscErrorCode ubr_free(void *p) { return PetscFree(p); }
