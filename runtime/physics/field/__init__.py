"""The field off the plate's axis: the exact magnetic fields of the base plates in closed form
(exact_field, the references the Laplace expansion of thesis eqs. 2.2.2-2.2.7 is judged against),
and how much an answer moves with the order at which that expansion is cut (truncation, `by_order`).
The bottom room of runtime/physics/: it imports nothing of the others."""
