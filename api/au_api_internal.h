/* au_api_internal.h - what the two files of api/ share: the target's topology expectation and the
 * flow's options behind au_options and au_expert. */
#ifndef AU_API_INTERNAL_H
#define AU_API_INTERNAL_H

#include "au_advect.h"
#include "au_mesh.h"
#include "au_sphere.h"
#include "authalic.h"

/* The topology a target needs (loops, genus 0), named by the target for messages. */
au_mesh_expect au__target_expect(au_target t);

/* The flow's options for target t (the sphere's or the planar defaults), with refine_faces applied;
 * sphere: the sphere's retries and vertex polish (au_sphere_opts_default; all 0 for the other targets). */
void au__flow_defaults(au_target t, int refine_faces, au_advect_opts *flow, au_sphere_opts *sphere);

/* Copy the tuning fields of e over f (the rest of f is left as it is). */
void au__flow_from_expert(const au_expert *e, au_advect_opts *f);

#endif
