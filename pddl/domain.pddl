; VSL-SP tabletop domain (Ahmadzadeh et al., Table 3): the preconditions and effects of the
; push and pull skills, as learned from pre-/post-action observations by
; vslsp.symbolic.learn_domain. (far ?b): the block lies beyond the landmark line.
(define (domain vsl-sp)
  (:requirements :strips :typing :negative-preconditions :constraints)
  (:types block)
  (:predicates
    (far ?b - block))

  (:action push
    :parameters (?b - block)
    :precondition (not (far ?b))
    :effect (far ?b))

  (:action pull
    :parameters (?b - block)
    :precondition (far ?b)
    :effect (not (far ?b))))
