; Blocks that are above one another: (above ?a ?b) is derived from (on ...), transitively.
(define (domain tower-derived)
  (:requirements :strips :typing :derived-predicates)
  (:types block)
  (:predicates (on ?a ?b - block) (clear ?b - block) (on-table ?b - block) (above ?a ?b - block))
  (:derived (above ?a ?b - block)
    (or (on ?a ?b) (exists (?c - block) (and (on ?a ?c) (above ?c ?b)))))
  (:action stack
    :parameters (?a ?b - block)
    :precondition (and (clear ?a) (clear ?b) (on-table ?a) (not (= ?a ?b)))
    :effect (and (on ?a ?b) (not (clear ?b)) (not (on-table ?a)))))
