(define (domain sorting)
  (:requirements :strips :typing)
  (:types item bin colour)
  (:predicates (in ?i - item ?b - bin) (on-table ?i - item) (colour-of ?i - item ?c - colour) (bin-colour ?b - bin ?c - colour))
  (:action sort
    :parameters (?i - item ?b - bin ?c - colour)
    :precondition (and (on-table ?i) (colour-of ?i ?c) (bin-colour ?b ?c))
    :effect (and (in ?i ?b) (not (on-table ?i)))))
